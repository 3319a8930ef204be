#include "gaitlab/robot.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "spec/check.h"

namespace gaitlab {

const char* to_string(Connection c) {
    switch (c) {
        case Connection::pitch_pitch:
            return "pitch-pitch";
        case Connection::pitch_yaw:
            return "pitch-yaw";
        case Connection::yaw_yaw:
            return "yaw-yaw";
    }
    return "?";
}

const char* to_string(JointRole r) {
    switch (r) {
        case JointRole::pitch:
            return "pitch";
        case JointRole::yaw:
            return "yaw";
        case JointRole::roll:
            return "roll";
    }
    return "?";
}

Connection parse_connection(std::string_view name) {
    for (Connection c : {Connection::pitch_pitch, Connection::pitch_yaw, Connection::yaw_yaw}) {
        if (name == to_string(c)) return c;
    }
    throw SpecError(fmt::format(
        "unknown connection type '{}' (expected 'pitch-pitch', 'pitch-yaw' or 'yaw-yaw')", name));
}

namespace {

JointRole role_of(const ModuleDef& m, Connection c, int joint) {
    if (m.axis == JointAxis::twist) return JointRole::roll;
    switch (c) {
        case Connection::pitch_pitch:
            return JointRole::pitch;
        case Connection::yaw_yaw:
            return JointRole::yaw;
        case Connection::pitch_yaw:
            return joint % 2 == 0 ? JointRole::pitch : JointRole::yaw;
    }
    return JointRole::pitch;
}

}  // namespace

RobotSpec make_chain(const ChainSpec& spec) {
    if (spec.modules < 1) {
        throw SpecError(fmt::format("modules must be at least 1 (got {})", spec.modules));
    }
    if (spec.modules > kMaxModules) {
        throw SpecError(
            fmt::format("modules must be at most {} (got {})", kMaxModules, spec.modules));
    }
    detail::check_name("robot name", spec.name);
    validate(spec.module);
    const ModuleDef& m = spec.module;
    const bool box = m.shape == Shape::box;
    // a pitch-yaw chain turns every other module by 90 degrees about the chain's axis, which
    // one rigid body per segment can only represent for a symmetric cross-section
    if (box && spec.connection == Connection::pitch_yaw && m.width != m.height) {
        throw SpecError(fmt::format(
            "a pitch-yaw chain needs modules with a square cross-section (module '{}' is {} x {} "
            "m; make width = height or use a cylinder)",
            m.name, m.width, m.height));
    }
    const Vec3 section = box ? Vec3{0, m.width, m.height} : Vec3{0, 2 * m.radius, 2 * m.radius};
    const double len = m.length, z = section.z / 2;
    const int n = spec.modules;

    RobotSpec robot;
    robot.name = spec.name;
    // the joint sits at each module's mid-plane, so the bodies are a tail half, n - 1 segments
    // made of two halves of neighbouring modules, and a head half
    auto add_body = [&](std::string name, double x0, double x1, double mass) {
        BodySpec b;
        b.name = std::move(name);
        b.shape = m.shape;
        b.size = {x1 - x0, section.y, section.z};
        b.mass = mass;
        b.pose.position = {(x0 + x1) / 2, 0, z};
        b.friction = m.friction;
        robot.bodies.push_back(std::move(b));
    };
    add_body("tail", 0, len / 2, m.mass / 2);
    for (int k = 1; k < n; ++k) {
        add_body(fmt::format("segment{}", k), len * (k - 0.5), len * (k + 0.5), m.mass);
    }
    add_body("head", len * (n - 0.5), len * n, m.mass / 2);

    for (int j = 0; j < n; ++j) {
        JointSpec js;
        js.name = fmt::format("joint{}", j + 1);
        js.role = role_of(m, spec.connection, j);
        js.parent = j;
        js.child = j + 1;
        js.pivot = {len * (j + 0.5), 0, z};
        // a positive pitch lifts the head side; a positive yaw turns it counter-clockwise seen
        // from +z; a positive roll turns it counter-clockwise seen from the head
        js.axis = js.role == JointRole::pitch ? Vec3{0, -1, 0}
                  : js.role == JointRole::yaw ? Vec3{0, 0, 1}
                                              : Vec3{1, 0, 0};
        js.min_angle = m.min_angle;
        js.max_angle = m.max_angle;
        js.servo = m.servo;
        robot.joints.push_back(std::move(js));
    }
    robot.chain = spec;
    return robot;
}

namespace {

// a given inertia (the body's mass and size already checked): positive, about each axis between
// kMinInertiaFraction of the uniform solid's and all of its mass at the body's half diagonal (no
// mass inside its size turns slower), no more uneven than the most slender body's, and a
// physical body's (each moment at most the sum of the other two). `q` starts the messages
// ("robot 'r' body 'b' ")
void check_inertia(const std::string& q, const BodySpec& b) {
    const Vec3& i = *b.inertia;
    const Vec3& s = b.size;
    BodySpec uniform = b;
    uniform.inertia.reset();
    const Vec3 solid = body_inertia(uniform);
    const double hi = b.mass * (s.x * s.x + s.y * s.y + s.z * s.z) / 4;
    const std::pair<const char*, double> moments[] = {{"x", i.x}, {"y", i.y}, {"z", i.z}};
    const double solids[] = {solid.x, solid.y, solid.z};
    for (int k = 0; k < 3; ++k) {
        const auto [axis, v] = moments[k];
        const std::string what = q + "inertia " + axis;
        detail::check_positive(what, v, "kg·m²");
        const double lo = kMinInertiaFraction * solids[k];
        // to a millionth: a bound as its message prints it (6 digits), or written as the
        // solid's / 100, is inside
        if (!(v >= lo * (1 - 1e-6) && v <= hi * (1 + 1e-6))) {
            throw SpecError(fmt::format(
                "{} must be in [{:.6g}, {:.6g}] kg·m² for its mass and size (got {}): from {} of "
                "the uniform solid's to all of its mass at half its diagonal",
                what, lo, hi, v, kMinInertiaFraction));
        }
    }
    const std::string got = fmt::format("got {} {} {} kg·m²", i.x, i.y, i.z);
    const double most = std::max({i.x, i.y, i.z}), least = std::min({i.x, i.y, i.z});
    if (most > kMaxInertiaRatio * least) {
        throw SpecError(fmt::format(
            "{}inertia's largest moment must be at most {} times its smallest, as a body's at "
            "most {} times as long as wide ({}: {:.6g} times)",
            q, kMaxInertiaRatio, kMaxBodySlenderness, got, most / least));
    }
    // to a millionth of the largest: a plate's moments written in six digits still pass
    for (int k = 0; k < 3; ++k) {
        const auto [axis, v] = moments[k];
        const double others = moments[(k + 1) % 3].second + moments[(k + 2) % 3].second;
        if (v > others + 1e-6 * most) {
            throw SpecError(fmt::format(
                "{}inertia must have each moment at most the sum of the other two, as every "
                "body's has ({}: {} is {}, the other two add up to {})",
                q, got, axis, v, others));
        }
    }
}

// a centre of mass (the body's size already checked): finite and inside the shape, its
// boundary included (all the mass on a face). Outside it no mass of the shape puts it, and a
// contact's lever about it would be longer than the body
void check_center_of_mass(const std::string& q, const BodySpec& b) {
    const Vec3& c = *b.center_of_mass;
    const std::string what = q + "com";
    for (double v : {c.x, c.y, c.z})
        detail::check_finite(what, v);
    // a billionth over: a centre of mass on a face stays inside when a URDF file's turned link
    // frame has rounded its last bits
    const Vec3 h = b.size * (0.5 * (1 + 1e-9));
    const std::string got = fmt::format("got {} {} {} m", c.x, c.y, c.z);
    if (b.shape == Shape::cylinder) {
        const double r = h.y;
        if (!(std::abs(c.x) <= h.x && std::hypot(c.y, c.z) <= r)) {
            throw SpecError(fmt::format(
                "{} must lie inside the cylinder: x within ±{:.6g} m (half its length), y and z "
                "within {:.6g} m of its axis (its radius) ({})",
                what, h.x, r, got));
        }
        return;
    }
    if (!(std::abs(c.x) <= h.x && std::abs(c.y) <= h.y && std::abs(c.z) <= h.z)) {
        throw SpecError(fmt::format(
            "{} must lie inside the box: each coordinate within half its size, ±{:.6g} ±{:.6g} "
            "±{:.6g} m ({})",
            what, h.x, h.y, h.z, got));
    }
}

}  // namespace

void validate_body(const std::string& robot_name, const BodySpec& b) {
    const std::string q = "robot '" + robot_name + "' body '" + b.name + "' ";
    detail::check_name(q + "name", b.name);
    detail::check_mass(q + "mass", b.mass, kMinBodyMass, kMaxBodyMass);
    detail::check_size(q + "size x", b.size.x, kMinBodyExtent, kMaxBodyExtent);
    // a cylinder's size y and z are its diameter
    const bool cylinder = b.shape == Shape::cylinder;
    const double min_section = cylinder ? 2 * kMinCylinderRadius : kMinBodyExtent;
    const char* const section = cylinder ? " (a cylinder's diameter)" : "";
    detail::check_size(q + "size y" + section, b.size.y, min_section, kMaxBodyExtent);
    detail::check_size(q + "size z" + section, b.size.z, min_section, kMaxBodyExtent);
    detail::check_range(q + "friction", b.friction, 0, 1);
    if (b.shape == Shape::cylinder && b.size.y != b.size.z) {
        throw SpecError(q + "is a cylinder: size y and z (its diameter) must be equal");
    }
    if (cylinder) {
        detail::check_cylinder_slenderness(q, b.size.x, b.size.y, kMaxBodySlenderness);
    } else {
        detail::check_box_slenderness(q, b.size, kMaxBodySlenderness);
    }
    const Vec3& x = b.pose.position;
    for (double c : {x.x, x.y, x.z})
        detail::check_within(q + "position", c, kMaxBodyExtent * kMaxRobotBodies, "m");
    const Quat& o = b.pose.orientation;
    if (!(std::abs(o.w * o.w + o.x * o.x + o.y * o.y + o.z * o.z - 1) < 1e-6)) {
        throw SpecError(q + "orientation must be a unit quaternion");
    }
    if (b.inertia) check_inertia(q, b);
    if (b.center_of_mass) check_center_of_mass(q, b);
}

void validate_joint(const RobotSpec& robot, const JointSpec& j) {
    const std::string q = "robot '" + robot.name + "' joint '" + j.name + "' ";
    detail::check_name(q + "name", j.name);
    const int nb = static_cast<int>(robot.bodies.size());
    if (j.parent < 0 || j.parent >= nb || j.child < 0 || j.child >= nb || j.parent == j.child) {
        throw SpecError(q + "must join two different bodies of the robot");
    }
    if (!(std::abs(j.axis.norm() - 1) <= 1e-6)) throw SpecError(q + "axis must be a unit vector");
    for (double c : {j.pivot.x, j.pivot.y, j.pivot.z})
        detail::check_within(q + "pivot", c, kMaxBodyExtent * kMaxRobotBodies, "m");
    if (!(j.min_angle < j.max_angle)) throw SpecError(q + "range must have min < max");
    detail::check_finite(q + "range min", j.min_angle);
    detail::check_finite(q + "range max", j.max_angle);
    // the bounds of a module's range (module.cpp): a joint turns at most half a turn either way
    if (!(j.min_angle >= -kPi && j.max_angle <= kPi)) {
        throw SpecError(
            fmt::format("{}range must satisfy -180 <= min < max <= 180 deg (got {} to "
                        "{} deg)",
                        q, rad_to_deg(j.min_angle), rad_to_deg(j.max_angle)));
    }
    detail::check_servo(q, j.servo);
}

void validate_name(const std::string& what, std::string_view name) {
    detail::check_name(what, name);
}

void validate(const RobotSpec& robot) {
    const std::string p = "robot '" + robot.name + "' ";
    if (robot.name.empty()) throw SpecError("a robot needs a name");
    detail::check_name("robot name", robot.name);
    if (robot.bodies.empty()) throw SpecError(p + "has no bodies");
    if (robot.bodies.size() > static_cast<size_t>(kMaxRobotBodies) ||
        robot.joints.size() > static_cast<size_t>(kMaxRobotBodies)) {
        throw SpecError(fmt::format("{}has {} bodies and {} joints (at most {} of each)", p,
                                    robot.bodies.size(), robot.joints.size(), kMaxRobotBodies));
    }
    // files refer to bodies by name: they must be unique (a set keeps this linear-log)
    std::set<std::string_view> names;
    for (const BodySpec& b : robot.bodies) {
        validate_body(robot.name, b);
        if (!names.insert(b.name).second) {
            throw SpecError(p + "has two bodies named '" + b.name + "'");
        }
    }
    names.clear();
    for (const JointSpec& j : robot.joints) {
        if (!names.insert(j.name).second) {
            throw SpecError(p + "has two joints named '" + j.name + "'");
        }
        validate_joint(robot, j);
    }
    validate_sensors(robot);
}

std::vector<int> select_joints(const RobotSpec& robot, std::string_view role) {
    const bool all = role == "all";
    if (!all && role != "pitch" && role != "yaw" && role != "roll") {
        throw SpecError(fmt::format(
            "unknown joint role '{}' (expected 'pitch', 'yaw', 'roll' or 'all')", role));
    }
    std::vector<int> out;
    for (int j = 0; j < static_cast<int>(robot.joints.size()); ++j) {
        if (all || role == to_string(robot.joints[j].role)) out.push_back(j);
    }
    if (out.empty()) {
        throw SpecError(fmt::format("robot '{}' has no {} joints", robot.name, role));
    }
    return out;
}

bool operator==(const BodySpec& a, const BodySpec& b) {
    return a.name == b.name && a.shape == b.shape && a.size == b.size && a.mass == b.mass &&
           a.pose.position == b.pose.position && a.pose.orientation == b.pose.orientation &&
           a.friction == b.friction && a.inertia == b.inertia &&
           a.center_of_mass == b.center_of_mass;
}

bool operator==(const JointSpec& a, const JointSpec& b) {
    return a.name == b.name && a.role == b.role && a.parent == b.parent && a.child == b.child &&
           a.pivot == b.pivot && a.axis == b.axis && a.min_angle == b.min_angle &&
           a.max_angle == b.max_angle && a.servo == b.servo;
}

bool operator==(const ChainSpec& a, const ChainSpec& b) {
    return a.name == b.name && a.modules == b.modules && a.connection == b.connection &&
           a.module == b.module;
}

bool operator==(const SensorSpec& a, const SensorSpec& b) {
    return a.kind == b.kind && a.name == b.name && a.module == b.module && a.joint == b.joint &&
           a.half == b.half && a.direction == b.direction && a.max_range == b.max_range &&
           a.enabled == b.enabled;
}

bool operator==(const RobotSpec& a, const RobotSpec& b) {
    return a.name == b.name && a.bodies == b.bodies && a.joints == b.joints &&
           a.self_collision == b.self_collision && a.chain == b.chain && a.sensors == b.sensors;
}

Vec3 body_inertia(const BodySpec& b) {
    if (b.inertia) return *b.inertia;
    const Vec3& s = b.size;
    const double m = b.mass / 12;
    if (b.shape == Shape::box) {
        return {m * (s.y * s.y + s.z * s.z), m * (s.x * s.x + s.z * s.z),
                m * (s.x * s.x + s.y * s.y)};
    }
    // a cylinder along x: size y is its diameter
    const double r = s.y / 2;
    const double across = m * (3 * r * r + s.x * s.x);
    return {b.mass * r * r / 2, across, across};
}

double total_mass(const RobotSpec& robot) {
    double m = 0;
    for (const BodySpec& b : robot.bodies)
        m += b.mass;
    return m;
}

}  // namespace gaitlab
