#pragma once

#include <gaitlab/high.h>

#include "low/a.h"
