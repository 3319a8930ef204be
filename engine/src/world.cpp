#include "gaitlab/world.h"

#include <fmt/format.h>

#include "check.h"
#include "gaitlab/error.h"

namespace gaitlab {

namespace {

// "stairs 2 " etc.: how messages name an object
std::string object_name(const char* kind, int number) {
    return fmt::format("{} {} ", kind, number);
}

void check_position(const std::string& p, const Vec3& v) {
    detail::check_finite(p + "position x", v.x);
    detail::check_finite(p + "position y", v.y);
    detail::check_finite(p + "position z", v.z);
}

void check_orientation(const std::string& p, const Quat& q) {
    if (!(std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) &&
          std::abs(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z - 1) < 1e-6)) {
        throw SpecError(p + "orientation must be a unit quaternion");
    }
}

void check_placement(const std::string& p, const Vec3& position, double yaw, double friction) {
    check_position(p, position);
    detail::check_finite(p + "yaw", yaw);
    detail::check_range(p + "friction", friction, 0, 1);
}

// integer counts: `what` must be in [lo, hi]
void check_count(const std::string& what, long long v, long long lo, long long hi) {
    if (v < lo || v > hi) {
        throw SpecError(fmt::format("{} must be in [{}, {}] (got {})", what, lo, hi, v));
    }
}

// `hi` must not be below `lo` (a range given by two fields)
void check_order(const std::string& p, const char* lo_name, double lo, const char* hi_name,
                 double hi) {
    if (hi < lo) {
        throw SpecError(fmt::format("{}{} must not be below {} (got {} < {} m)", p, hi_name,
                                    lo_name, detail::shown(hi), detail::shown(lo)));
    }
}

}  // namespace

void validate(const BoxSpec& b, int number) {
    const std::string p = object_name("box", number);
    detail::check_positive(p + "size x", b.size.x, "m");
    detail::check_positive(p + "size y", b.size.y, "m");
    detail::check_positive(p + "size z", b.size.z, "m");
    detail::check_non_negative(p + "mass", b.mass, "kg");
    detail::check_range(p + "friction", b.friction, 0, 1);
    check_position(p, b.pose.position);
    check_orientation(p, b.pose.orientation);
}

void validate(const WallSpec& w, int number) {
    const std::string p = object_name("wall", number);
    detail::check_positive(p + "length", w.length, "m");
    detail::check_positive(p + "height", w.height, "m");
    detail::check_positive(p + "thickness", w.thickness, "m");
    check_placement(p, w.position, w.yaw, w.friction);
}

void validate(const RampSpec& r, int number) {
    const std::string p = object_name("ramp", number);
    if (!(std::isfinite(r.slope) && r.slope > 0 && r.slope < kPi / 2)) {
        throw SpecError(fmt::format(
            "{}slope must be between 0 and 90 deg, both excluded (got {})", p,
            std::isnan(r.slope) ? "nan" : fmt::format("{:.6g} deg", rad_to_deg(r.slope))));
    }
    detail::check_positive(p + "length", r.length, "m");
    detail::check_positive(p + "width", r.width, "m");
    check_placement(p, r.position, r.yaw, r.friction);
}

void validate(const StairsSpec& s, int number) {
    const std::string p = object_name("stairs", number);
    check_count(p + "steps", s.steps, 1, 1000);
    detail::check_positive(p + "step_height", s.step_height, "m");
    detail::check_positive(p + "step_depth", s.step_depth, "m");
    detail::check_positive(p + "width", s.width, "m");
    detail::check_non_negative(p + "landing", s.landing, "m");
    check_placement(p, s.position, s.yaw, s.friction);
}

void validate(const CylinderSpec& c, int number) {
    const std::string p = object_name("cylinder", number);
    detail::check_positive(p + "radius", c.radius, "m");
    detail::check_positive(p + "length", c.length, "m");
    detail::check_non_negative(p + "mass", c.mass, "kg");
    check_placement(p, c.position, c.yaw, c.friction);
}

void validate(const PipeSpec& t, int number) {
    const std::string p = object_name("pipe", number);
    detail::check_positive(p + "radius", t.radius, "m");
    detail::check_positive(p + "thickness", t.thickness, "m");
    detail::check_positive(p + "length", t.length, "m");
    check_count(p + "sides", t.sides, 3, 256);
    check_placement(p, t.position, t.yaw, t.friction);
}

void validate(const RubbleSpec& r, int number) {
    const std::string p = object_name("rubble", number);
    detail::check_positive(p + "length", r.length, "m");
    detail::check_positive(p + "width", r.width, "m");
    check_count(p + "count", r.count, 0, 100000);
    detail::check_positive(p + "min_size", r.min_size, "m");
    detail::check_positive(p + "max_size", r.max_size, "m");
    check_order(p, "min_size", r.min_size, "max_size", r.max_size);
    detail::check_positive(p + "min_height", r.min_height, "m");
    detail::check_positive(p + "max_height", r.max_height, "m");
    check_order(p, "min_height", r.min_height, "max_height", r.max_height);
    check_placement(p, r.position, r.yaw, r.friction);
}

void validate(const HeightfieldSpec& h, int number) {
    const std::string p = object_name("heightfield", number);
    detail::check_positive(p + "length", h.length, "m");
    detail::check_positive(p + "width", h.width, "m");
    if (h.heights.empty()) {
        if (h.image.empty()) throw SpecError(p + "needs heights or an image");
        detail::check_positive(p + "max_height", h.max_height, "m");
    } else {
        if (!h.image.empty()) throw SpecError(p + "has both heights and an image (give one)");
        check_count(p + "samples_x", h.samples_x, 2, 4096);
        check_count(p + "samples_y", h.samples_y, 2, 4096);
        const size_t n = static_cast<size_t>(h.samples_x) * static_cast<size_t>(h.samples_y);
        if (h.heights.size() != n) {
            throw SpecError(fmt::format("{}needs samples_x · samples_y = {} heights (got {})", p, n,
                                        h.heights.size()));
        }
        for (size_t k = 0; k < n; ++k) {
            if (!std::isfinite(h.heights[k])) {
                throw SpecError(
                    fmt::format("{}height at grid point ({}, {}) must be a finite number", p,
                                k % static_cast<size_t>(h.samples_x) + 1,
                                k / static_cast<size_t>(h.samples_x) + 1));
            }
        }
    }
    check_placement(p, h.position, h.yaw, h.friction);
}

void validate(const WorldSpec& world) {
    detail::check_finite("gravity x", world.gravity.x);
    detail::check_finite("gravity y", world.gravity.y);
    detail::check_finite("gravity z", world.gravity.z);
    detail::check_range("floor friction", world.floor.friction, 0, 1);
    // each kind is numbered from 1 in its own vector
    auto each = [](const auto& objects) {
        for (size_t i = 0; i < objects.size(); ++i)
            validate(objects[i], static_cast<int>(i + 1));
    };
    each(world.boxes);
    each(world.walls);
    each(world.ramps);
    each(world.stairs);
    each(world.cylinders);
    each(world.pipes);
    each(world.rubble);
    each(world.heightfields);
    for (const PlacedRobot& r : world.robots) {
        validate(r.robot);
        check_position("robot '" + r.robot.name + "' ", r.pose.position);
        check_orientation("robot '" + r.robot.name + "' ", r.pose.orientation);
    }
}

}  // namespace gaitlab
