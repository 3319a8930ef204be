#include "gaitlab/checked.h"

#include <cmath>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "spec/check.h"

namespace gaitlab {

long long checked_integer(std::string_view what, long long v, long long lo, long long hi) {
    if (v < lo || v > hi) {
        throw SpecError(fmt::format("{} must be in [{}, {}] (got {})", what, lo, hi, v));
    }
    return v;
}

int checked_int(std::string_view what, long long v, int lo, int hi) {
    return static_cast<int>(checked_integer(what, v, lo, hi));
}

long long checked_whole(std::string_view what, double v, long long lo, long long hi) {
    // compared as doubles first: a value far beyond long long must not be converted
    if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi)) || v != std::floor(v)) {
        throw SpecError(fmt::format("{} must be {}in [{}, {}] (got {})", what,
                                    std::isfinite(v) && v != std::floor(v) ? "a whole number " : "",
                                    lo, hi, detail::shown(v)));
    }
    return static_cast<long long>(v);
}

}  // namespace gaitlab
