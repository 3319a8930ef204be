#pragma once

#include "gaitlab/low.h"
