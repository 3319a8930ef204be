#include "low/a.h"

#include "high/b.h"
#include "gaitlab/high.h"
#include <gaitlab/high.h>
#include "../high/b.h"
  #  include "a.h"
// #include "high/b.h" in a comment is no include
