#include "gaitlab/module.h"

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/robot.h"
#include "spec/check.h"

namespace gaitlab {

const char* to_string(JointAxis a) {
    return a == JointAxis::bend ? "bend" : "twist";
}

ModuleDef cube_module_def() {
    ModuleDef m;
    m.name = "cube";
    m.length = 0.06;
    m.width = 0.06;
    m.height = 0.06;
    m.radius = 0.03;
    m.mass = 0.1;
    // a standard-size high-torque hobby servo: about 10 kg·cm and 0.2 s per 60 degrees
    m.servo.max_torque = 1.0;
    m.servo.max_speed = 5.2;
    return m;
}

const std::vector<ModuleDef>& builtin_modules() {
    static const std::vector<ModuleDef> modules{default_module_def(), cube_module_def()};
    return modules;
}

ModuleDef builtin_module(std::string_view name) {
    std::string names;
    for (const ModuleDef& m : builtin_modules()) {
        if (m.name == name) return m;
        names += (names.empty() ? "'" : ", '") + m.name + "'";
    }
    throw SpecError(fmt::format("unknown module type '{}' (built in: {})", name, names));
}

void validate(const ModuleDef& m) {
    const std::string p = "module '" + m.name + "' ";
    if (m.name.empty()) throw SpecError("a module type needs a name");
    detail::check_name("module name", m.name);
    // the limits of the bodies a chain makes of it (robot.h), whose two end bodies are half a
    // module: half its length and half its mass
    detail::check_size(p + "length", m.length, 2 * kMinBodyExtent, kMaxBodyExtent);
    if (m.shape == Shape::box) {
        detail::check_size(p + "width", m.width, kMinBodyExtent, kMaxBodyExtent);
        detail::check_size(p + "height", m.height, kMinBodyExtent, kMaxBodyExtent);
    } else {
        detail::check_size(p + "radius", m.radius, kMinCylinderRadius, kMaxBodyExtent / 2);
    }
    // a chain's segments are a module long and its two end bodies half of one
    if (m.shape == Shape::box) {
        const Vec3 segment{m.length, m.width, m.height}, end{m.length / 2, m.width, m.height};
        const bool ends = detail::slenderness(end) > detail::slenderness(segment);
        detail::check_box_slenderness(p + "bodies' ", ends ? end : segment, kMaxBodySlenderness,
                                      ends ? "; its end bodies are half a module" : "");
    } else {
        detail::check_cylinder_slenderness(p, m.length, 2 * m.radius, kMaxBodySlenderness);
    }
    detail::check_mass(p + "mass", m.mass, 2 * kMinBodyMass, kMaxBodyMass);
    detail::check_range(p + "friction", m.friction, 0, 1);
    detail::check_servo(p, m.servo);
    if (!(m.min_angle < m.max_angle && m.min_angle >= -kPi && m.max_angle <= kPi)) {
        throw SpecError(p + "joint range must satisfy -180 <= min < max <= 180 deg");
    }
}

}  // namespace gaitlab
