// Module types: the building blocks robots are chained from, and the module library.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "gaitlab/types.h"

namespace gaitlab {

/// The largest servo gain, 1/s: a time constant (1 / kp) no shorter than the smallest dt, 1 µs.
inline constexpr double kMaxServoKp = 1e6;
/// The largest servo speed, rad/s (about 9500 rpm; hobby servos turn at 5 to 35 rad/s).
inline constexpr double kMaxServoSpeed = 1000;
/// The largest servo torque, N·m: holds the heaviest body (1e6 kg) out level at the end of the
/// longest (100 m) under Earth's gravity.
inline constexpr double kMaxServoTorque = 1e9;

/// A position servo like a hobby RC servo: omega_cmd = clamp(kp * (target - angle), +-max_speed),
/// applied as a velocity motor whose torque is limited to max_torque.
struct ServoDef {
    double kp = 8.3;          ///< proportional gain, 1/s, in (0, kMaxServoKp]
    double max_speed = 4.5;   ///< rad/s, in (0, kMaxServoSpeed]
    double max_torque = 0.4;  ///< N·m, in (0, kMaxServoTorque]
};

inline bool operator==(const ServoDef& a, const ServoDef& b) {
    return a.kp == b.kp && a.max_speed == b.max_speed && a.max_torque == b.max_torque;
}

/// The servo of the y1 module (Futaba S3003 as modelled by OpenMR).
inline ServoDef default_servo_def() {
    return ServoDef{};
}

/// Which way a module's joint turns.
enum class JointAxis {
    bend,   ///< across the chain: a pitch or a yaw joint, as the chain's connection says
    twist,  ///< along the chain: a roll joint, the head side turns about the chain's axis
};

/// "bend" or "twist".
const char* to_string(JointAxis a);

/// A module type: a box or a cylinder cut in two rigid halves by the joint at its mid-plane.
/// The default values are the y1 module's.
struct ModuleDef {
    std::string name = "y1";   ///< the name messages and the library use
    Shape shape = Shape::box;  ///< a cylinder's axis runs along the chain
    double length = 0.072;     ///< joint-to-joint length along the chain, m
    double width = 0.052;      ///< box: cross-section side along the pitch axis, m
    double height = 0.052;     ///< box: cross-section side along the yaw axis, m
    double radius = 0.026;     ///< cylinder: cross-section radius, m
    double mass = 0.05;        ///< kg, split equally between the two halves
    JointAxis axis = JointAxis::bend;
    double min_angle = -1.5707963267948966;  ///< joint range lower end, rad
    double max_angle = 1.5707963267948966;   ///< joint range upper end, rad
    double friction = 1.0;  ///< surface friction in [0, 1]; contacts multiply the two surfaces'
    ServoDef servo = default_servo_def();
};

inline bool operator==(const ModuleDef& a, const ModuleDef& b) {
    return a.name == b.name && a.shape == b.shape && a.length == b.length && a.width == b.width &&
           a.height == b.height && a.radius == b.radius && a.mass == b.mass && a.axis == b.axis &&
           a.min_angle == b.min_angle && a.max_angle == b.max_angle && a.friction == b.friction &&
           a.servo == b.servo;
}
inline bool operator!=(const ModuleDef& a, const ModuleDef& b) {
    return !(a == b);
}

/// The default y1 module: 72 mm joint to joint, 52 × 52 mm, 50 g, ±90°, 0.4 N·m, 4.5 rad/s.
inline ModuleDef default_module_def() {
    return ModuleDef{};
}

/// The cube module: a 60 mm cube, 100 g, ±90°, 1.0 N·m, 5.2 rad/s. Illustrative numbers for a
/// module built around a standard-size high-torque hobby servo (see docs/modules.md).
ModuleDef cube_module_def();

/// The module library: every built-in module type ("y1", "cube"), the default first.
const std::vector<ModuleDef>& builtin_modules();

/// The built-in module type called `name`; throws SpecError naming the valid names.
ModuleDef builtin_module(std::string_view name);

/// Checks sizes, mass, friction, joint range and servo (messages start "module 'NAME' ");
/// throws SpecError.
void validate(const ModuleDef& module);

}  // namespace gaitlab
