#include "gaitlab/world.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "spec/check.h"

namespace gaitlab {

namespace {

// "stairs 2 " etc.: how messages name an object
std::string object_name(const char* kind, int number) {
    return fmt::format("{} {} ", kind, number);
}

void check_position(const std::string& p, const Vec3& v) {
    detail::check_within(p + "position x", v.x, kMaxCoordinate, "m");
    detail::check_within(p + "position y", v.y, kMaxCoordinate, "m");
    detail::check_within(p + "position z", v.z, kMaxCoordinate, "m");
}

void check_size(const std::string& what, double v) {
    detail::check_size(what, v, kMinExtent, kMaxExtent);
}

// 0 (static), or a mass that moves the object as physics says
void check_mass(const std::string& what, double v) {
    detail::check_non_negative(what, v, "kg");
    if (v > 0 && v < kMinObjectMass) {
        throw SpecError(fmt::format("{} must be 0 (static) or at least {} kg (got {} kg)", what,
                                    kMinObjectMass, v));
    }
    detail::check_at_most(what, v, kMaxObjectMass, "kg");
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
    const double degrees = rad_to_deg(yaw);
    if (std::abs(degrees) > kMaxAngleDegrees) {
        // in degrees, as files and scripts give it, without the conversion's last digit
        // unless that digit is what puts it outside
        std::string shown = fmt::format("{:.12g}", degrees);
        if (std::abs(std::stod(shown)) <= kMaxAngleDegrees) shown = fmt::format("{}", degrees);
        throw SpecError(fmt::format("{}yaw must be in [-{}, {}] deg (got {})", p, kMaxAngleDegrees,
                                    kMaxAngleDegrees, shown));
    }
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
    check_size(p + "size x", b.size.x);
    check_size(p + "size y", b.size.y);
    check_size(p + "size z", b.size.z);
    check_mass(p + "mass", b.mass);
    if (b.mass > 0) {
        detail::check_box_slenderness(p, b.size, kMaxBodySlenderness,
                                      "; a static box, of mass 0, may be more slender");
    }
    detail::check_range(p + "friction", b.friction, 0, 1);
    check_position(p, b.pose.position);
    check_orientation(p, b.pose.orientation);
}

void validate(const WallSpec& w, int number) {
    const std::string p = object_name("wall", number);
    check_size(p + "length", w.length);
    check_size(p + "height", w.height);
    check_size(p + "thickness", w.thickness);
    check_placement(p, w.position, w.yaw, w.friction);
}

void validate(const RampSpec& r, int number) {
    const std::string p = object_name("ramp", number);
    if (!(std::isfinite(r.slope) && r.slope > 0 && r.slope < kPi / 2)) {
        throw SpecError(fmt::format(
            "{}slope must be between 0 and 90 deg, both excluded (got {})", p,
            std::isnan(r.slope) ? "nan" : fmt::format("{:.6g} deg", rad_to_deg(r.slope))));
    }
    check_size(p + "length", r.length);
    check_size(p + "width", r.width);
    check_size(p + "height", r.length * std::tan(r.slope));
    check_placement(p, r.position, r.yaw, r.friction);
}

void validate(const StairsSpec& s, int number) {
    const std::string p = object_name("stairs", number);
    check_count(p + "steps", s.steps, 1, kMaxStairsSteps);
    check_size(p + "step_height", s.step_height);
    check_size(p + "step_depth", s.step_depth);
    check_size(p + "width", s.width);
    detail::check_non_negative(p + "landing", s.landing, "m");
    detail::check_at_most(p + "landing", s.landing, kMaxExtent, "m");
    check_size(p + "height", s.steps * s.step_height);
    check_size(p + "length", s.steps * s.step_depth + s.landing);
    check_placement(p, s.position, s.yaw, s.friction);
}

void validate(const CylinderSpec& c, int number) {
    const std::string p = object_name("cylinder", number);
    detail::check_size(p + "radius", c.radius, kMinCylinderRadius, kMaxExtent);
    check_size(p + "length", c.length);
    check_mass(p + "mass", c.mass);
    if (c.mass > 0) {
        detail::check_cylinder_slenderness(p, c.length, 2 * c.radius, kMaxBodySlenderness,
                                           "; a static cylinder, of mass 0, may be more slender");
    }
    check_placement(p, c.position, c.yaw, c.friction);
}

void validate(const PipeSpec& t, int number) {
    const std::string p = object_name("pipe", number);
    check_size(p + "radius", t.radius);
    check_size(p + "thickness", t.thickness);
    check_size(p + "length", t.length);
    check_count(p + "sides", t.sides, 3, kMaxPipeSides);
    check_placement(p, t.position, t.yaw, t.friction);
}

void validate(const RubbleSpec& r, int number) {
    const std::string p = object_name("rubble", number);
    check_size(p + "length", r.length);
    check_size(p + "width", r.width);
    check_count(p + "count", r.count, 0, kMaxRubbleCount);
    check_size(p + "min_size", r.min_size);
    check_size(p + "max_size", r.max_size);
    check_order(p, "min_size", r.min_size, "max_size", r.max_size);
    check_size(p + "min_height", r.min_height);
    check_size(p + "max_height", r.max_height);
    check_order(p, "min_height", r.min_height, "max_height", r.max_height);
    check_placement(p, r.position, r.yaw, r.friction);
}

void validate(const HeightfieldSpec& h, int number) {
    const std::string p = object_name("heightfield", number);
    check_size(p + "length", h.length);
    check_size(p + "width", h.width);
    if (h.heights.empty()) {
        if (h.image.empty()) throw SpecError(p + "needs heights or an image");
        detail::check_size(p + "max_height", h.max_height, kMinExtent, kMaxTerrainHeight);
    } else {
        if (!h.image.empty()) throw SpecError(p + "has both heights and an image (give one)");
        check_count(p + "samples_x", h.samples_x, 2, kMaxHeightfieldSide);
        check_count(p + "samples_y", h.samples_y, 2, kMaxHeightfieldSide);
        const size_t n = static_cast<size_t>(h.samples_x) * static_cast<size_t>(h.samples_y);
        if (h.heights.size() != n) {
            throw SpecError(fmt::format("{}needs samples_x · samples_y = {} heights (got {})", p, n,
                                        h.heights.size()));
        }
        for (size_t k = 0; k < n; ++k) {
            if (!(std::abs(h.heights[k]) <= kMaxTerrainHeight)) {
                detail::check_within(fmt::format("{}height at grid point ({}, {})", p,
                                                 k % static_cast<size_t>(h.samples_x) + 1,
                                                 k / static_cast<size_t>(h.samples_x) + 1),
                                     h.heights[k], kMaxTerrainHeight, "m");
            }
        }
    }
    check_placement(p, h.position, h.yaw, h.friction);
}

long long solid_count(const WorldSpec& world) {
    long long n =
        static_cast<long long>(world.boxes.size() + world.walls.size() + world.ramps.size() +
                               world.cylinders.size() + world.heightfields.size());
    for (const StairsSpec& s : world.stairs)
        n += std::max(s.steps, 0);
    for (const PipeSpec& p : world.pipes)
        n += std::max(p.sides, 0);
    for (const RubbleSpec& r : world.rubble)
        n += std::max(r.count, 0);
    return n;
}

void validate(const WorldSpec& world) {
    detail::check_within("gravity x", world.gravity.x, kMaxGravity, "m/s²");
    detail::check_within("gravity y", world.gravity.y, kMaxGravity, "m/s²");
    detail::check_within("gravity z", world.gravity.z, kMaxGravity, "m/s²");
    detail::check_range("floor friction", world.floor.friction, 0, 1);
    const FloorSpec& floor = world.floor;
    if (floor.rigid && (floor.stiffness || floor.damping)) {
        throw SpecError(
            fmt::format("a rigid floor takes no {} (a floor is rigid, or compliant "
                        "with a stiffness and a damping)",
                        floor.stiffness ? "stiffness" : "damping"));
    }
    if (floor.stiffness) {
        detail::check_positive("floor stiffness", *floor.stiffness, "N/m");
        detail::check_at_most("floor stiffness", *floor.stiffness, kMaxFloorStiffness, "N/m");
    }
    if (floor.damping) {
        detail::check_non_negative("floor damping", *floor.damping, "N·s/m");
        detail::check_at_most("floor damping", *floor.damping, kMaxFloorDamping, "N·s/m");
    }
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
    // every object was within its own limits; together they must fit too
    const long long solids = solid_count(world);
    if (solids > kMaxWorldSolids) {
        throw SpecError(
            fmt::format("the world's objects make {} rigid bodies (at most {}: "
                        "fewer stones, steps or objects)",
                        solids, kMaxWorldSolids));
    }
    long long samples = 0;
    for (const HeightfieldSpec& h : world.heightfields)
        samples += static_cast<long long>(h.heights.size());
    if (samples > kMaxHeightSamples) {
        throw SpecError(
            fmt::format("the world's heightfields have {} samples together (at most "
                        "{})",
                        samples, kMaxHeightSamples));
    }
    if (world.robots.size() > static_cast<size_t>(kMaxRobots)) {
        throw SpecError(fmt::format("a world holds at most {} robots (got {})", kMaxRobots,
                                    world.robots.size()));
    }
    for (const PlacedRobot& r : world.robots) {
        validate(r.robot);
        check_position("robot '" + r.robot.name + "' ", r.pose.position);
        check_orientation("robot '" + r.robot.name + "' ", r.pose.orientation);
    }
}

}  // namespace gaitlab
