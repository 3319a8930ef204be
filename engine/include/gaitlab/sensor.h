// Sensor specs: plain values attached to a robot (RobotSpec::sensors), one per sensor, and the
// named channels each kind of sensor reports. A simulation compiles them and updates the ones
// that are switched on once per tick (see simulation.h and docs/sensors.md).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "gaitlab/types.h"

namespace gaitlab {

struct RobotSpec;

/// What a sensor measures.
enum class SensorKind {
    joint,    ///< one joint: angle, velocity, torque
    imu,      ///< one half of a module: orientation, angular velocity, specific force
    contact,  ///< one module: whether it touches anything, and the normal force
    range,    ///< a ray from one half of a module: distance to the first object it meets
    position  ///< the robot: centre of mass and its velocity
};

/// The two rigid halves of a module, cut by its joint: the tail side (the joint's parent body)
/// and the head side (its child body).
enum class ModuleHalf { tail, head };

/// "joint", "imu", "contact", "range" or "position".
const char* to_string(SensorKind kind);
/// "tail" or "head".
const char* to_string(ModuleHalf half);
/// Every sensor kind's name, in declaration order.
const std::vector<std::string>& sensor_kind_names();
/// Parses a kind name; throws SpecError naming the valid ones.
SensorKind parse_sensor_kind(std::string_view name);
/// Parses "tail" or "head"; throws SpecError.
ModuleHalf parse_module_half(std::string_view name);

/// One sensor of a robot. Fields that do not apply to its kind are ignored (and not stored by
/// the file formats). Module m of a robot is the module of its joint m: the bodies that joint
/// joins are the module's two halves.
struct SensorSpec {
    SensorKind kind = SensorKind::imu;
    /// unique within the robot: letters, digits and '_'; "" takes default_sensor_name()
    std::string name;
    int module = 0;                      ///< imu, contact, range: 0-based module index
    int joint = 0;                       ///< joint: 0-based joint index
    ModuleHalf half = ModuleHalf::head;  ///< imu, range: the half that carries the sensor
    Vec3 direction{1, 0, 0};             ///< range: ray direction in that half's frame, != 0
    double max_range = 2.0;              ///< range: m, in [kMinRange, kMaxRange]
    bool enabled = true;                 ///< switched on (updated every tick) or off
};

/// Sensors one robot may carry.
inline constexpr int kMaxSensors = 10000;

/// Limits of SensorSpec::max_range, m.
constexpr double kMinRange = 0.01;
constexpr double kMaxRange = 100.0;

/// "joint3", "imu3", "contact3", "range3" (1-based, as users number them) or "position".
std::string default_sensor_name(const SensorSpec& sensor);
/// The sensor's name: its own, or the default one.
std::string sensor_name(const SensorSpec& sensor);

/// Checks one sensor against `robot` (module or joint it names, max_range, direction, name,
/// and that no sensor of robot.sensors has the same name); throws SpecError.
void validate_sensor(const RobotSpec& robot, const SensorSpec& sensor);
/// Checks every sensor of `robot` (as validate_sensor, names unique); throws SpecError.
void validate_sensors(const RobotSpec& robot);

/// One value a sensor reports.
struct SensorChannel {
    std::string name;      ///< "angle", "roll", "distance" ...
    std::string unit;      ///< engine units: "rad", "rad/s", "m", "m/s", "m/s²", "N", "N·m", ""
    bool boolean = false;  ///< 0 or 1 (Lua shows false or true)
};

/// The channels of a kind, in the order of a sensor's values (engine units: radians inside).
///
///   joint     angle rad, velocity rad/s, torque N·m
///   imu       roll pitch yaw rad, qw qx qy qz, wx wy wz rad/s, ax ay az m/s²
///   contact   contact (boolean), force N
///   range     distance m, hit (boolean)
///   position  x y z m, vx vy vz m/s
const std::vector<SensorChannel>& sensor_channels(SensorKind kind);
/// Index of the channel called `name` of `kind`, or -1.
int find_sensor_channel(SensorKind kind, std::string_view name);

/// The unit a user sees at the Lua boundary and in recordings: "deg" for "rad", "deg/s" for
/// "rad/s", otherwise the engine unit.
std::string user_unit(const SensorChannel& channel);
/// A value in user units (degrees for angles).
double to_user_units(const SensorChannel& channel, double value);

}  // namespace gaitlab
