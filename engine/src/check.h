// Validation helpers for the engine's spec checks: each throws SpecError with the expected form.
#pragma once

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "gaitlab/error.h"

namespace gaitlab::detail {

/// A number as messages show it: "nan" whatever its sign bit.
inline std::string shown(double v) {
    return std::isnan(v) ? "nan" : fmt::format("{}", v);
}

/// `what` must be a finite number in [lo, hi].
inline void check_range(const std::string& what, double v, double lo, double hi,
                        const char* unit = "") {
    if (!(std::isfinite(v) && v >= lo && v <= hi)) {
        throw SpecError(fmt::format("{} must be in [{}, {}]{}{} (got {})", what, lo, hi,
                                    *unit ? " " : "", unit, shown(v)));
    }
}

/// `what` must be a finite number > 0.
inline void check_positive(const std::string& what, double v, const char* unit = "") {
    if (!(std::isfinite(v) && v > 0)) {
        throw SpecError(fmt::format("{} must be positive (got {}{}{})", what, shown(v),
                                    *unit ? " " : "", unit));
    }
}

/// `what` must be a finite number >= 0.
inline void check_non_negative(const std::string& what, double v, const char* unit = "") {
    if (!(std::isfinite(v) && v >= 0)) {
        throw SpecError(fmt::format("{} must not be negative (got {}{}{})", what, shown(v),
                                    *unit ? " " : "", unit));
    }
}

inline void check_finite(const std::string& what, double v) {
    if (!std::isfinite(v)) throw SpecError(fmt::format("{} must be a finite number", what));
}

}  // namespace gaitlab::detail
