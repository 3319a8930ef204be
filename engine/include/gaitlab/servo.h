// The servo law shared by every joint.
#pragma once

#include <algorithm>

#include "gaitlab/module.h"

namespace gaitlab {

/// Speed command of a position servo, rad/s: clamp(kp * (target - angle), +-max_speed).
/// The physics applies it as a velocity motor limited to servo.max_torque.
inline double servo_command(const ServoDef& servo, double target, double angle) {
    const double w = servo.kp * (target - angle);
    return std::clamp(w, -servo.max_speed, servo.max_speed);
}

}  // namespace gaitlab
