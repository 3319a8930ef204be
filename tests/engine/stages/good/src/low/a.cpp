#include "low/a.h"

#include <liblow/x.h>

#include "a.h"
