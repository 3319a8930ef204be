#include "high/b.h"

#include <libhigh.h>

#include "../low/a.h"
#include "b.h"
#include "gaitlab/low.h"
