// Validation helpers for the engine's spec checks: each throws SpecError with the expected form.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/module.h"
#include "gaitlab/terminal.h"

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

/// `what` must be a finite number in [-limit, limit] (non-finite: check_finite's message).
inline void check_within(const std::string& what, double v, double limit, const char* unit = "") {
    check_finite(what, v);
    if (std::abs(v) > limit) {
        throw SpecError(fmt::format("{} must be in [{}, {}]{}{} (got {})", what, -limit, limit,
                                    *unit ? " " : "", unit, v));
    }
}

/// `what`, already known to be a number, must not exceed `hi`.
inline void check_at_most(const std::string& what, double v, double hi, const char* unit = "") {
    if (v > hi) {
        throw SpecError(fmt::format("{} must be at most {}{}{} (got {}{}{})", what, hi,
                                    *unit ? " " : "", unit, v, *unit ? " " : "", unit));
    }
}

/// `what`, already known to be a number, must not be below `lo`.
inline void check_at_least(const std::string& what, double v, double lo, const char* unit = "") {
    if (v < lo) {
        throw SpecError(fmt::format("{} must be at least {}{}{} (got {}{}{})", what, lo,
                                    *unit ? " " : "", unit, v, *unit ? " " : "", unit));
    }
}

/// A size: positive, in [lo, hi] (a positive size below `lo` is refused with `lo`).
inline void check_size(const std::string& what, double v, double lo, double hi,
                       const char* unit = "m") {
    check_positive(what, v, unit);
    check_at_least(what, v, lo, unit);
    check_at_most(what, v, hi, unit);
}

/// A mass: positive, in [lo, hi] kg.
inline void check_mass(const std::string& what, double v, double lo, double hi) {
    check_positive(what, v, "kg");
    check_at_least(what, v, lo, "kg");
    check_at_most(what, v, hi, "kg");
}

/// The longest of a body's three sides (m) over the second longest: how slender it is.
inline double slenderness(const Vec3& size) {
    double a = size.x, b = size.y, c = size.z;
    if (a < b) std::swap(a, b);
    if (a < c) std::swap(a, c);
    return a / std::max(b, c);
}

/// A box of sides `size` (m, each already checked) must have its longest side at most `limit`
/// times its second longest; `note` ends the message ("" or "; ...").
inline void check_box_slenderness(const std::string& what, const Vec3& size, double limit,
                                  const std::string& note = "") {
    const double s = slenderness(size);
    if (s > limit) {
        throw SpecError(
            fmt::format("{}longest side must be at most {} times its second longest "
                        "(got {} x {} x {} m: {:.6g} times{})",
                        what, limit, size.x, size.y, size.z, s, note));
    }
}

/// A cylinder `length` long and `diameter` wide (m, each already checked) must be at most
/// `limit` times as long as it is wide; `note` ends the message ("" or "; ...").
inline void check_cylinder_slenderness(const std::string& what, double length, double diameter,
                                       double limit, const std::string& note = "") {
    if (length > limit * diameter) {
        throw SpecError(
            fmt::format("{}length must be at most {} times its diameter (got {} m "
                        "and {} m: {:.6g} times{})",
                        what, limit, length, diameter, length / diameter, note));
    }
}

/// A servo's gain, speed and torque, each positive and at most its kMaxServo* bound (module.h:
/// far beyond any servo, and the motor's single-precision rows hold them). `p` starts the
/// messages ("module 'm' ").
inline void check_servo(const std::string& p, const ServoDef& s) {
    check_positive(p + "servo kp", s.kp, "1/s");
    check_at_most(p + "servo kp", s.kp, kMaxServoKp, "1/s");
    check_positive(p + "servo max_speed", s.max_speed, "rad/s");
    check_at_most(p + "servo max_speed", s.max_speed, kMaxServoSpeed, "rad/s");
    check_positive(p + "servo max_torque", s.max_torque, "N·m");
    check_at_most(p + "servo max_torque", s.max_torque, kMaxServoTorque, "N·m");
}

/// The longest name gaitlab accepts (robots, bodies, joints, modules, controllers), bytes.
inline constexpr size_t kMaxNameBytes = 256;

/// `name` as messages can show it whatever it holds: bytes outside printable ASCII as \xNN.
inline std::string escaped(std::string_view name) {
    std::string out;
    for (unsigned char c : name) {
        if (c >= 0x20 && c < 0x7f && c != '\\') {
            out += static_cast<char>(c);
        } else {
            out += fmt::format("\\x{:02x}", c);
        }
    }
    return out;
}

/// Whether `s` is valid UTF-8 (no overlong forms, no surrogates, nothing above U+10FFFF) without
/// control characters (U+0000-U+001F, U+007F-U+009F): what terminal_line leaves as it is.
inline bool printable_utf8(std::string_view s) {
    return terminal_line(s) == s;
}

/// `what` (e.g. "robot name") must be valid UTF-8 without control characters, at most
/// kMaxNameBytes long: names become series names, file names and JSON strings.
inline void check_name(const std::string& what, std::string_view name) {
    if (name.size() > kMaxNameBytes) {
        throw SpecError(fmt::format("{} must be at most {} bytes long (got {} bytes)", what,
                                    kMaxNameBytes, name.size()));
    }
    if (!printable_utf8(name)) {
        throw SpecError(fmt::format(
            "{} must be valid UTF-8 without control characters (got \"{}\")", what, escaped(name)));
    }
}

}  // namespace gaitlab::detail
