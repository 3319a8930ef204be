#include "gaitlab/sensor.h"

#include <cmath>
#include <set>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/robot.h"
#include "spec/check.h"

namespace gaitlab {

namespace {

constexpr SensorKind kKinds[] = {SensorKind::joint, SensorKind::imu, SensorKind::contact,
                                 SensorKind::range, SensorKind::position};

bool valid_name_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

// the checks of one sensor that do not depend on the robot's other sensors
void check_sensor(const RobotSpec& robot, const SensorSpec& s, const std::string& name) {
    // the module or joint first: an unnamed sensor's name is made of its number ('imu-1')
    const int nj = static_cast<int>(robot.joints.size());
    switch (s.kind) {
        case SensorKind::joint:
            if (s.joint < 0 || s.joint >= nj) {
                if (nj == 0) throw SpecError(fmt::format("robot '{}' has no joints", robot.name));
                throw SpecError(fmt::format("robot '{}' has no joint {} (it has joints 1 to {})",
                                            robot.name, s.joint + 1, nj));
            }
            break;
        case SensorKind::imu:
        case SensorKind::contact:
        case SensorKind::range:
            if (s.module < 0 || s.module >= nj) {
                if (nj == 0) {
                    throw SpecError(fmt::format("robot '{}' has no modules", robot.name));
                }
                throw SpecError(fmt::format("robot '{}' has no module {} (it has modules 1 to {})",
                                            robot.name, s.module + 1, nj));
            }
            break;
        case SensorKind::position:
            break;
    }
    detail::check_name("sensor name", name);
    for (char c : name) {
        if (!valid_name_char(c)) {
            throw SpecError(
                fmt::format("sensor name '{}' may contain only letters, digits and '_'", name));
        }
    }
    if (s.kind == SensorKind::range) {
        const std::string p = "sensor '" + name + "' ";
        detail::check_range(p + "max_range", s.max_range, kMinRange, kMaxRange, "m");
        const Vec3& d = s.direction;
        // any finite length but zero: {1e-300, 0, 0} too, whose norm underflows (sensing.cpp
        // scales the vector before it normalizes it)
        if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z) &&
              (d.x != 0 || d.y != 0 || d.z != 0))) {
            throw SpecError(p + "direction must be a non-zero vector");
        }
    }
}

std::vector<SensorChannel> channels(std::initializer_list<const char*> names, const char* unit) {
    std::vector<SensorChannel> out;
    for (const char* n : names)
        out.push_back({n, unit, false});
    return out;
}

template <class... Parts>
std::vector<SensorChannel> concat(Parts... parts) {
    std::vector<SensorChannel> out;
    (out.insert(out.end(), parts.begin(), parts.end()), ...);
    return out;
}

}  // namespace

const char* to_string(SensorKind kind) {
    switch (kind) {
        case SensorKind::joint:
            return "joint";
        case SensorKind::imu:
            return "imu";
        case SensorKind::contact:
            return "contact";
        case SensorKind::range:
            return "range";
        case SensorKind::position:
            return "position";
    }
    return "?";
}

const char* to_string(ModuleHalf half) {
    return half == ModuleHalf::tail ? "tail" : "head";
}

const std::vector<std::string>& sensor_kind_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (SensorKind k : kKinds)
            v.emplace_back(to_string(k));
        return v;
    }();
    return names;
}

SensorKind parse_sensor_kind(std::string_view name) {
    for (SensorKind k : kKinds) {
        if (name == to_string(k)) return k;
    }
    throw SpecError(fmt::format(
        "unknown sensor kind '{}' (expected 'joint', 'imu', 'contact', 'range' or 'position')",
        name));
}

ModuleHalf parse_module_half(std::string_view name) {
    if (name == "tail") return ModuleHalf::tail;
    if (name == "head") return ModuleHalf::head;
    throw SpecError(fmt::format("unknown module half '{}' (expected 'tail' or 'head')", name));
}

std::string default_sensor_name(const SensorSpec& s) {
    switch (s.kind) {
        case SensorKind::joint:
            return fmt::format("joint{}", s.joint + 1);
        case SensorKind::position:
            return "position";
        default:
            return fmt::format("{}{}", to_string(s.kind), s.module + 1);
    }
}

std::string sensor_name(const SensorSpec& s) {
    return s.name.empty() ? default_sensor_name(s) : s.name;
}

void validate_sensor(const RobotSpec& robot, const SensorSpec& sensor) {
    if (robot.sensors.size() >= static_cast<size_t>(kMaxSensors)) {
        throw SpecError(fmt::format("robot '{}' has {} sensors already (at most {})", robot.name,
                                    robot.sensors.size(), kMaxSensors));
    }
    const std::string name = sensor_name(sensor);
    check_sensor(robot, sensor, name);
    for (const SensorSpec& other : robot.sensors) {
        if (sensor_name(other) == name) {
            throw SpecError(fmt::format(
                "robot '{}' already has a sensor named '{}' (give this one another name)",
                robot.name, name));
        }
    }
}

void validate_sensors(const RobotSpec& robot) {
    if (robot.sensors.size() > static_cast<size_t>(kMaxSensors)) {
        throw SpecError(fmt::format("robot '{}' has {} sensors (at most {})", robot.name,
                                    robot.sensors.size(), kMaxSensors));
    }
    std::set<std::string> seen;
    for (const SensorSpec& s : robot.sensors) {
        const std::string name = sensor_name(s);
        check_sensor(robot, s, name);
        if (!seen.insert(name).second) {
            throw SpecError(fmt::format("robot '{}' has two sensors named '{}'", robot.name, name));
        }
    }
}

const std::vector<SensorChannel>& sensor_channels(SensorKind kind) {
    static const std::vector<SensorChannel> joint = {
        {"angle", "rad", false}, {"velocity", "rad/s", false}, {"torque", "N·m", false}};
    static const std::vector<SensorChannel> imu =
        concat(channels({"roll", "pitch", "yaw"}, "rad"), channels({"qw", "qx", "qy", "qz"}, ""),
               channels({"wx", "wy", "wz"}, "rad/s"), channels({"ax", "ay", "az"}, "m/s²"));
    static const std::vector<SensorChannel> contact = {{"contact", "", true},
                                                       {"force", "N", false}};
    static const std::vector<SensorChannel> range = {{"distance", "m", false}, {"hit", "", true}};
    static const std::vector<SensorChannel> position =
        concat(channels({"x", "y", "z"}, "m"), channels({"vx", "vy", "vz"}, "m/s"));
    switch (kind) {
        case SensorKind::joint:
            return joint;
        case SensorKind::imu:
            return imu;
        case SensorKind::contact:
            return contact;
        case SensorKind::range:
            return range;
        case SensorKind::position:
            return position;
    }
    return joint;
}

int find_sensor_channel(SensorKind kind, std::string_view name) {
    const auto& c = sensor_channels(kind);
    for (size_t i = 0; i < c.size(); ++i) {
        if (c[i].name == name) return static_cast<int>(i);
    }
    return -1;
}

std::string user_unit(const SensorChannel& channel) {
    if (channel.unit == "rad") return "deg";
    if (channel.unit == "rad/s") return "deg/s";
    return channel.unit;
}

double to_user_units(const SensorChannel& channel, double value) {
    if (channel.unit == "rad" || channel.unit == "rad/s") return rad_to_deg(value);
    return value;
}

}  // namespace gaitlab
