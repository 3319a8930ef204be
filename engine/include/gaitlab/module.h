// Module types: the building blocks robots are chained from.
#pragma once

#include <string>

namespace gaitlab {

/// A position servo like a hobby RC servo: omega_cmd = clamp(kp * (target - angle), +-max_speed),
/// applied as a velocity motor whose torque is limited to max_torque.
struct ServoDef {
    double kp = 8.3;          ///< proportional gain, 1/s
    double max_speed = 4.5;   ///< rad/s
    double max_torque = 0.4;  ///< N·m
};

inline bool operator==(const ServoDef& a, const ServoDef& b) {
    return a.kp == b.kp && a.max_speed == b.max_speed && a.max_torque == b.max_torque;
}

/// The servo of the y1 module (Futaba S3003 as modelled by OpenMR).
inline ServoDef default_servo_def() {
    return ServoDef{};
}

/// A module type: a box cut in two rigid halves by the joint at its mid-plane.
struct ModuleDef {
    std::string name = "y1";
    double length = 0.072;                   ///< joint-to-joint length along the chain, m
    double width = 0.052;                    ///< cross-section side across the chain, m
    double height = 0.052;                   ///< cross-section side, m
    double mass = 0.05;                      ///< kg, split equally between the two halves
    double min_angle = -1.5707963267948966;  ///< joint range lower end, rad
    double max_angle = 1.5707963267948966;   ///< joint range upper end, rad
    double friction = 1.0;  ///< surface friction in [0, 1]; contacts multiply the two surfaces'
    ServoDef servo = default_servo_def();
};

inline bool operator==(const ModuleDef& a, const ModuleDef& b) {
    return a.name == b.name && a.length == b.length && a.width == b.width && a.height == b.height &&
           a.mass == b.mass && a.min_angle == b.min_angle && a.max_angle == b.max_angle &&
           a.friction == b.friction && a.servo == b.servo;
}
inline bool operator!=(const ModuleDef& a, const ModuleDef& b) {
    return !(a == b);
}

/// The default y1 module: 72 mm joint to joint, 52 × 52 mm, 50 g, ±90°, 0.4 N·m, 4.5 rad/s.
inline ModuleDef default_module_def() {
    return ModuleDef{};
}

}  // namespace gaitlab
