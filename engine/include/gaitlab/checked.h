// Checked conversions of the numbers users give (through Lua or a file): a count, an index or
// a number of ticks either lies in the range it must lie in, or is rejected with that range.
// It never wraps, saturates or rounds into another value, so every narrowing of a
// user-supplied number goes through here.
#pragma once

#include <string_view>

namespace gaitlab {

/// `v` if it lies in [lo, hi]; otherwise SpecError "WHAT must be in [LO, HI] (got V)".
long long checked_integer(std::string_view what, long long v, long long lo, long long hi);

/// `v` as an int if it lies in [lo, hi] (checked_integer's message otherwise).
int checked_int(std::string_view what, long long v, int lo, int hi);

/// `v`, a number that must be whole (a Lua float, a count computed from seconds), if it lies in
/// [lo, hi]; otherwise SpecError "WHAT must be in [LO, HI] (got V)" (NaN and fractions too).
long long checked_whole(std::string_view what, double v, long long lo, long long hi);

}  // namespace gaitlab
