#pragma once
#include "gaitlab/high.h"
