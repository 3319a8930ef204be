#pragma once

#include <vector>

#include "gaitlab/low.h"
