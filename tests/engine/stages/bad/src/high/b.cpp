#include "high/b.h"

#include <liblow/x.h>
#include <vector>

#include "gaitlab/low.h"
#include "nowhere.h"
#include "unclosed.h
