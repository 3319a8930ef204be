// Lua tables read with the XML files' meaning (spec_fields.h).
#include "spec_fields.h"

#include <cmath>
#include <map>

#include <fmt/format.h>

#include "gaitlab/robot.h"
#include "gaitlab/suggest.h"
#include "scene.h"
#include "wrap.h"

namespace gaitlab::scripting {

Quat quat_field(lua_State* L, const Fields& f, const char* key, const Quat& fallback) {
    const int t = f.push(key);
    if (t == LUA_TNIL) {
        lua_pop(L, 1);
        return fallback;
    }
    const char* expected = "unit quaternion expected ({w, x, y, z})";
    if (t != LUA_TTABLE) {
        const std::string n = type_name(L, -1);
        lua_pop(L, 1);
        f.fail(key, fmt::format("{}, got {}", expected, n));
    }
    double c[4];
    f.numbers(key, {"w", "x", "y", "z"}, "unit quaternion", c);
    const double norm = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
    if (!(std::abs(norm - 1) <= 1e-6)) {
        f.fail(key, fmt::format("a unit quaternion expected (its norm is {})", norm));
    }
    return {c[0], c[1], c[2], c[3]};
}

Quat orientation_field(lua_State* L, const Fields& f) {
    if (f.has("yaw") && f.has("orientation")) {
        f.fail("orientation", "give 'yaw' or 'orientation', not both");
    }
    if (f.has("orientation")) return quat_field(L, f, "orientation", {});
    return Quat::from_axis_angle({0, 0, 1}, deg_to_rad(pose_angle_field(f, "yaw")));
}

double pose_angle_field(const Fields& f, const char* key) {
    const double degrees = f.number(key, 0);
    if (!(std::fabs(degrees) <= kMaxAngleDegrees)) {
        f.fail(key,
               fmt::format("a number of degrees in [-{0}, {0}] expected, got {1}", kMaxAngleDegrees,
                           std::isnan(degrees) ? "nan" : fmt::format("{}", degrees)));
    }
    return degrees;
}

namespace {

Shape shape_field(const Fields& f, Shape fallback) {
    const std::string s = f.string("shape", to_string(fallback));
    if (s == "box") return Shape::box;
    if (s == "cylinder") return Shape::cylinder;
    f.fail("shape", fmt::format("'box' or 'cylinder' expected, got '{}'", s));
}

JointRole role_field(const Fields& f) {
    const std::string role = f.string("role", "pitch");
    if (role == "pitch") return JointRole::pitch;
    if (role == "yaw") return JointRole::yaw;
    if (role == "roll") return JointRole::roll;
    f.fail("role", fmt::format("'pitch', 'yaw' or 'roll' expected, got '{}'", role));
}

// the body a joint's `key` names, among the robot's bodies
int body_field(const Fields& f, const std::map<std::string, int>& index, const char* key) {
    if (!f.has(key)) f.fail(key, "body name expected, got nil");
    const std::string name = f.string(key, "");
    const auto it = index.find(name);
    if (it != index.end()) return it->second;
    std::vector<std::string> names;
    for (const auto& [n, i] : index)
        names.push_back(n);
    f.fail(key, fmt::format("no body '{}' in the robot{}", name, did_you_mean(name, names)));
}

// calls `each` with the Fields of every entry of list field `key` ("bodies" or "joints": a list
// of tables); an error names the entry ("bodies[2]: field 'mass': ...")
template <class F>
void each_entry(lua_State* L, const Fields& f, const char* key, int arg, F&& each) {
    const int t = f.push(key);
    if (t != LUA_TTABLE) {
        const std::string n = type_name(L, -1);
        lua_pop(L, 1);
        f.fail(key, "list of tables expected, got " + n);
    }
    const int list = lua_gettop(L);
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, list));
    if (n > kMaxRobotBodies) {
        lua_pop(L, 1);
        f.fail(key, fmt::format("a robot has at most {} {}", kMaxRobotBodies, key));
    }
    for (lua_Integer i = 1; i <= n; ++i) {
        const std::string prefix = fmt::format("{}[{}]: ", key, i);
        if (lua_rawgeti(L, list, i) != LUA_TTABLE) {
            const std::string tn = type_name(L, -1);
            lua_settop(L, list - 1);
            throw ArgError(arg, prefix + "table expected, got " + tn);
        }
        try {
            // the attributes of <body> and <joint>
            if (std::string(key) == "bodies") {
                const Fields e(L, lua_gettop(L), arg,
                               {"name", "shape", "size", "mass", "position", "orientation",
                                "friction", "inertia", "com"});
                each(e);
            } else {
                const Fields e(L, lua_gettop(L), arg,
                               {"name", "role", "parent", "child", "pivot", "axis", "min", "max",
                                "kp", "max_speed", "max_torque"});
                each(e);
            }
        } catch (const ArgError& err) {
            lua_settop(L, list - 1);
            throw ArgError(arg, prefix + err.what());
        } catch (const SpecError& err) {
            lua_settop(L, list - 1);
            throw ArgError(arg, prefix + err.what());
        }
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
}

}  // namespace

double servo_speed_field(const Fields& f, const char* key, double fallback) {
    const double speed = f.number(key, rad_to_deg(fallback));
    const double most = rad_to_deg(kMaxServoSpeed);
    if (!(speed > 0 && speed <= most)) {
        f.fail(key, fmt::format("must be in (0, {}] deg/s (got {} deg/s)", most, speed));
    }
    return deg_to_rad(speed);
}

int robot_new(lua_State* L) {
    return protect(L, [&] {
        Fields f(L, 1, 1, {"name", "self_collision", "bodies", "joints"});
        RobotSpec robot;
        robot.name = f.string("name", "robot");
        robot.self_collision = f.boolean("self_collision", false);
        std::map<std::string, int> names;
        each_entry(L, f, "bodies", 1, [&](const Fields& e) {
            BodySpec b;
            if (!e.has("name")) e.fail("name", "string expected, got nil");
            b.name = e.string("name", "");
            if (names.count(b.name))
                e.fail("name", fmt::format("a second body named '{}'", b.name));
            b.shape = shape_field(e, Shape::box);
            if (!e.has("size")) e.fail("size", "vector expected ({x, y, z}, m), got nil");
            b.size = e.vec3("size", {});
            if (!e.has("mass")) e.fail("mass", "number expected (kg), got nil");
            b.mass = e.number("mass", 0);
            b.pose.position = e.vec3("position", {});
            b.pose.orientation = quat_field(L, e, "orientation", {});
            b.friction = e.number("friction", 1.0);
            if (e.has("inertia")) b.inertia = e.vec3("inertia", {});
            if (e.has("com")) b.center_of_mass = e.vec3("com", {});
            validate_body(robot.name, b);
            names.emplace(b.name, static_cast<int>(robot.bodies.size()));
            robot.bodies.push_back(b);
        });
        if (robot.bodies.empty()) f.fail("bodies", "a robot needs at least one body");
        if (f.push("joints") == LUA_TNIL) {
            lua_pop(L, 1);
        } else {
            lua_pop(L, 1);
            each_entry(L, f, "joints", 1, [&](const Fields& e) {
                JointSpec j;
                if (!e.has("name")) e.fail("name", "string expected, got nil");
                j.name = e.string("name", "");
                j.role = role_field(e);
                j.parent = body_field(e, names, "parent");
                j.child = body_field(e, names, "child");
                if (!e.has("pivot")) e.fail("pivot", "vector expected ({x, y, z}, m), got nil");
                j.pivot = e.vec3("pivot", {});
                if (!e.has("axis")) e.fail("axis", "unit vector expected ({x, y, z}), got nil");
                j.axis = e.vec3("axis", {});
                const ModuleDef y1 = default_module_def();
                j.min_angle = e.has("min") ? deg_to_rad(e.number("min", 0)) : y1.min_angle;
                j.max_angle = e.has("max") ? deg_to_rad(e.number("max", 0)) : y1.max_angle;
                j.servo.kp = e.number("kp", y1.servo.kp);
                // degrees per second, as every angle a script gives
                j.servo.max_speed = servo_speed_field(e, "max_speed", y1.servo.max_speed);
                j.servo.max_torque = e.number("max_torque", y1.servo.max_torque);
                validate_joint(robot, j);
                robot.joints.push_back(j);
            });
        }
        try {
            validate(robot);
        } catch (const SpecError& e) {
            throw ArgError(1, e.what());
        }
        auto binding = std::make_shared<RobotBinding>();
        binding->spec = std::move(robot);
        push_robot(L, std::move(binding));
        return 1;
    });
}

}  // namespace gaitlab::scripting
