// gaitlab.robot: chain builder, robot handles and joint groups.
#include <fmt/format.h>

#include "config_files.h"
#include "gaitlab/files.h"
#include "gaitlab/suggest.h"
#include "gaitlab/urdf.h"
#include "lua_util.h"
#include "recording.h"
#include "scene.h"
#include "spec_fields.h"
#include "wrap.h"

namespace gaitlab::scripting {

// a group is named by its robot and its joints in their order (their order is the
// controller's: {1, 3} and {3, 1} are two groups)
HandleKey handle_key(const GroupHandle& group) {
    return {group.robot.get(), fmt::format("{}", fmt::join(group.joints, " "))};
}

namespace {

using RobotPtr = std::shared_ptr<RobotBinding>;

RobotBinding& check_robot(lua_State* L, int index) {
    return *check_object<RobotPtr>(L, index, kRobotType);
}

int robot_chain(lua_State* L) {
    return protect(L, [&] {
        Fields f(L, 1, 1, {"name", "modules", "connection", "module", "self_collision"});
        ChainSpec spec;
        const bool self_collision = f.boolean("self_collision", false);
        spec.name = f.string("name", "robot");
        if (!f.has("modules")) f.fail("modules", "number of modules expected, got nil");
        // checked before it becomes an int (make_chain's words for make_chain's range), so a
        // count beyond int never wraps into a valid one
        const long long modules = f.integer("modules", 0);
        if (modules < 1) {
            throw ArgError(1, fmt::format("modules must be at least 1 (got {})", modules));
        }
        if (modules > kMaxModules) {
            throw ArgError(
                1, fmt::format("modules must be at most {} (got {})", kMaxModules, modules));
        }
        spec.modules = static_cast<int>(modules);
        if (f.push("module") != LUA_TNIL) {
            try {
                spec.module = to_module(L, -1);
            } catch (const Error& e) {
                lua_pop(L, 1);
                f.fail("module", e.what());
            }
        }
        lua_pop(L, 1);
        try {
            spec.connection = parse_connection(f.string("connection", "pitch-pitch"));
            auto robot = std::make_shared<RobotBinding>();
            robot->spec = make_chain(spec);
            robot->spec.self_collision = self_collision;
            push_robot(L, std::move(robot));
        } catch (const SpecError& e) {
            throw ArgError(1, e.what());
        }
        return 1;
    });
}

int robot_group(lua_State* L) {
    return protect(L, [&] {
        RobotPtr& robot = check_object<RobotPtr>(L, 1, kRobotType);
        const RobotSpec& spec = robot->spec;
        std::vector<int> joints;
        if (lua_type(L, 2) == LUA_TSTRING) {
            try {
                joints = select_joints(spec, check_string(L, 2));
            } catch (const SpecError& e) {
                throw ArgError(2, e.what());
            }
        } else if (lua_istable(L, 2)) {
            const auto n = static_cast<lua_Integer>(lua_rawlen(L, 2));
            if (n == 0) throw ArgError(2, "a joint group needs at least one joint");
            const int nj = static_cast<int>(spec.joints.size());
            for (lua_Integer i = 1; i <= n; ++i) {
                lua_rawgeti(L, 2, i);
                lua_Integer j = 0;
                const bool ok = read_integer(L, -1, j).empty();
                lua_pop(L, 1);
                if (!ok) throw ArgError(2, fmt::format("entry {} is not a joint number", i));
                if (j < 1 || j > nj) {
                    throw ArgError(2, fmt::format("robot '{}' has no joint {} (it has joints 1 "
                                                  "to {})",
                                                  spec.name, j, nj));
                }
                for (int k : joints) {
                    if (k == j - 1) throw ArgError(2, fmt::format("joint {} is listed twice", j));
                }
                joints.push_back(static_cast<int>(j - 1));
            }
        } else {
            throw ArgError(
                2,
                "role ('pitch', 'yaw', 'roll', 'all') or list of joint numbers expected, "
                "got " +
                    type_name(L, 2));
        }
        push_canonical<GroupHandle>(L, kGroupType, GroupHandle{robot, std::move(joints)});
        return 1;
    });
}

int robot_position(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        push_vec3(L, r.live()->robot_position(r.index));
        return 1;
    });
}

int robot_velocity(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        push_vec3(L, r.live()->robot_velocity(r.index));
        return 1;
    });
}

int robot_displacement(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        push_vec3(L, r.live()->robot_displacement(r.index));
        return 1;
    });
}

// robot:heading(): degrees in (-180, 180], tail-to-head direction on the floor, from +x
// towards +y (docs/conventions.md)
int robot_heading(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        lua_pushnumber(L, rad_to_deg(r.live()->robot_heading(r.index)));
        return 1;
    });
}

// robot:turned(): degrees turned since the simulation started, counter-clockwise positive,
// not wrapped
int robot_turned(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        lua_pushnumber(L, rad_to_deg(r.live()->robot_turned(r.index)));
        return 1;
    });
}

int robot_energy(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        lua_pushnumber(L, r.live()->robot_energy(r.index));
        return 1;
    });
}

int robot_bodies(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        auto sim = r.sim.lock();
        const auto& bodies = r.spec.bodies;
        lua_createtable(L, static_cast<int>(bodies.size()), 0);
        for (size_t b = 0; b < bodies.size(); ++b) {
            lua_createtable(L, 0, 8);
            lua_pushstring(L, bodies[b].name.c_str());
            lua_setfield(L, -2, "name");
            lua_pushnumber(L, bodies[b].mass);
            lua_setfield(L, -2, "mass");
            push_vec3(L, body_inertia(bodies[b]));
            lua_setfield(L, -2, "inertia");
            // the centre of mass in the body's frame, from its shape's centre (zero: there)
            push_vec3(L, bodies[b].center_of_mass.value_or(Vec3{}));
            lua_setfield(L, -2, "com");
            push_vec3(L, bodies[b].size);
            lua_setfield(L, -2, "size");
            lua_pushstring(L, to_string(bodies[b].shape));
            lua_setfield(L, -2, "shape");
            if (sim) {
                set_body_state(L, sim->body(r.index, static_cast<int>(b)));
            }
            lua_rawseti(L, -2, static_cast<lua_Integer>(b + 1));
        }
        return 1;
    });
}

int robot_joints(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        auto sim = r.sim.lock();
        const auto& joints = r.spec.joints;
        std::vector<double> energies;  // J, filled for a robot in a simulation
        lua_createtable(L, static_cast<int>(joints.size()), 0);
        for (size_t j = 0; j < joints.size(); ++j) {
            lua_createtable(L, 0, 10);
            lua_pushinteger(L, static_cast<lua_Integer>(j + 1));
            lua_setfield(L, -2, "index");
            lua_pushstring(L, joints[j].name.c_str());
            lua_setfield(L, -2, "name");
            lua_pushstring(L, to_string(joints[j].role));
            lua_setfield(L, -2, "role");
            lua_pushnumber(L, rad_to_deg(joints[j].min_angle));
            lua_setfield(L, -2, "min");
            lua_pushnumber(L, rad_to_deg(joints[j].max_angle));
            lua_setfield(L, -2, "max");
            if (sim) {
                if (energies.empty()) {
                    energies.resize(joints.size());
                    sim->joint_energies(r.index, energies.data());
                }
                const JointState s = sim->joint(r.index, static_cast<int>(j));
                lua_pushnumber(L, rad_to_deg(s.angle));
                lua_setfield(L, -2, "angle");
                lua_pushnumber(L, rad_to_deg(s.target));
                lua_setfield(L, -2, "target");
                lua_pushnumber(L, rad_to_deg(s.velocity));
                lua_setfield(L, -2, "velocity");
                lua_pushnumber(L, s.torque);
                lua_setfield(L, -2, "torque");
                lua_pushnumber(L, energies[j]);
                lua_setfield(L, -2, "energy");
            }
            lua_rawseti(L, -2, static_cast<lua_Integer>(j + 1));
        }
        return 1;
    });
}

int robot_index(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        const std::string key = lua_type(L, 2) == LUA_TSTRING ? to_string(L, 2) : "";
        if (key == "name") {
            lua_pushstring(L, r.spec.name.c_str());
            return 1;
        }
        // what the chain was built from: { modules =, connection =, module = }, nil otherwise
        if (key == "chain") {
            if (!r.spec.chain) {
                lua_pushnil(L);
                return 1;
            }
            const ChainSpec& c = *r.spec.chain;
            lua_createtable(L, 0, 3);
            lua_pushinteger(L, c.modules);
            lua_setfield(L, -2, "modules");
            lua_pushstring(L, to_string(c.connection));
            lua_setfield(L, -2, "connection");
            lua_pushstring(L, c.module.name.c_str());
            lua_setfield(L, -2, "module");
            return 1;
        }
        raw_getfield(L, lua_upvalueindex(1), key);
        return 1;
    });
}

int robot_tostring(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        const size_t n = r.spec.joints.size();
        lua_pushfstring(L, "gaitlab.Robot '%s' (%d joint%s)", r.spec.name.c_str(),
                        static_cast<int>(n), n == 1 ? "" : "s");
        return 1;
    });
}

int robot_eq(lua_State* L) {
    return handle_eq<RobotPtr>(L, kRobotType);
}

int robot_len(lua_State* L) {
    return protect(L, [&] {
        lua_pushinteger(L, static_cast<lua_Integer>(check_robot(L, 1).spec.joints.size()));
        return 1;
    });
}

// gaitlab.robot.load(path): a robot from a robot file, or nil and a message
int robot_load(lua_State* L) {
    return protect(L, [&] {
        const std::string arg = check_string(L, 1);
        return file_read(L, [&] {
            const std::string path = checked_input_path(L, arg);
            auto robot = std::make_shared<RobotBinding>();
            robot->spec = read_robot(path);
            push_robot(L, std::move(robot));
        });
    });
}

// robot:save(path): writes the robot file; the path, or nil and a message
int robot_save(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        const ScriptPath path(L, check_string(L, 2));
        return file_written(L, path, [&] { write_robot(path.path(), r.spec); });
    });
}

// gaitlab.robot.load_urdf(path [, { inertia = "file" | "shapes" }]): a robot from a URDF
// serial chain, or nil and a message
int robot_load_urdf(lua_State* L) {
    return protect(L, [&] {
        const std::string arg = check_string(L, 1);
        UrdfImport how;
        if (!lua_isnoneornil(L, 2)) {
            Fields f(L, 2, 2, {"inertia"});
            const std::string inertia = f.string("inertia", "file");
            if (inertia != "file" && inertia != "shapes") {
                f.fail("inertia",
                       "\"file\" (each link's <inertial> as the file gives it) or "
                       "\"shapes\" (each link a uniform solid of its shape and mass) "
                       "expected, got \"" +
                           inertia + "\"" + did_you_mean(inertia, {"file", "shapes"}));
            }
            how.inertia_from_shapes = inertia == "shapes";
        }
        return file_read(L, [&] {
            const std::string path = checked_input_path(L, arg);
            auto robot = std::make_shared<RobotBinding>();
            robot->spec = read_urdf(path, how);
            push_robot(L, std::move(robot));
        });
    });
}

// robot:save_urdf(path): writes the robot as URDF; the path, or nil and a message
int robot_save_urdf(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        const ScriptPath path(L, check_string(L, 2));
        // a robot URDF cannot hold (joints that are no tree) is a failure to write, as the
        // docs promise: nil and the message, not an error that ends the script
        std::optional<std::string> cannot;
        try {
            return file_written(L, path, [&] { write_urdf(path.path(), r.spec); });
        } catch (const SpecError& e) {
            cannot = path.shown(path.path()) + ": " + e.what();
        }
        return push_fail(L, *cannot);
    });
}

// robot:actuation(): the spec of its groups and controllers, parameters at their current values
int robot_actuation(lua_State* L) {
    return protect(L, [&] {
        new_object<ActuationSpec>(L, kActuationType, actuation_of(check_robot(L, 1)));
        return 1;
    });
}

// robot:actuate(actuation): drives the robot as the spec says; returns its controllers
int robot_actuate(lua_State* L) {
    return protect(L, [&] {
        RobotBinding& r = check_robot(L, 1);
        const ActuationSpec& a = check_object<ActuationSpec>(L, 2, kActuationType);
        std::vector<std::shared_ptr<Controller>> made;
        try {
            made = actuate(L, r, a);
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        lua_createtable(L, static_cast<int>(made.size()), 0);
        for (size_t i = 0; i < made.size(); ++i) {
            push_controller(L, made[i], true);
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

// robot:controllers(): the controllers driving the robot's groups, in the order they were added
int robot_controllers(lua_State* L) {
    return protect(L, [&] {
        const RobotBinding& r = check_robot(L, 1);
        lua_createtable(L, static_cast<int>(r.drives.size()), 0);
        for (size_t i = 0; i < r.drives.size(); ++i) {
            push_controller(L, r.drives[i].controller, true);
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

int group_drive(lua_State* L) {
    return protect(L, [&] {
        GroupHandle& g = check_object<GroupHandle>(L, 1, kGroupType);
        ControllerHandle& c = check_object<ControllerHandle>(L, 2, kControllerType);
        if (c.attached) {
            throw ArgError(2, "controller '" + c.controller->name() +
                                  "' already drives a group (create one controller per group)");
        }
        g.robot->drive(g.joints, c.controller, default_origin(L));
        c.attached = true;
        lua_settop(L, 2);
        return 1;
    });
}

int group_joints(lua_State* L) {
    return protect(L, [&] {
        GroupHandle& g = check_object<GroupHandle>(L, 1, kGroupType);
        lua_createtable(L, static_cast<int>(g.joints.size()), 0);
        for (size_t i = 0; i < g.joints.size(); ++i) {
            lua_pushinteger(L, g.joints[i] + 1);
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

int group_eq(lua_State* L) {
    return handle_eq<GroupHandle>(L, kGroupType);
}

int group_len(lua_State* L) {
    return protect(L, [&] {
        lua_pushinteger(
            L, static_cast<lua_Integer>(check_object<GroupHandle>(L, 1, kGroupType).joints.size()));
        return 1;
    });
}

}  // namespace

bool is_robot(lua_State* L, int index) {
    return luaL_testudata(L, index, kRobotType) != nullptr;
}

void push_robot(lua_State* L, std::shared_ptr<RobotBinding> robot) {
    push_canonical<RobotPtr>(L, kRobotType, std::move(robot));
}

std::shared_ptr<RobotBinding> to_robot(lua_State* L, int index) {
    return check_object<RobotPtr>(L, index, kRobotType);
}

void open_robot(lua_State* L) {
    const luaL_Reg methods[] = {{"group", robot_group},
                                {"position", robot_position},
                                {"velocity", robot_velocity},
                                {"displacement", robot_displacement},
                                {"heading", robot_heading},
                                {"turned", robot_turned},
                                {"energy", robot_energy},
                                {"bodies", robot_bodies},
                                {"joints", robot_joints},
                                {"save", robot_save},
                                {"save_urdf", robot_save_urdf},
                                {"actuation", robot_actuation},
                                {"actuate", robot_actuate},
                                {"controllers", robot_controllers},
                                {"sensor", robot_sensor},
                                {"sensors", robot_sensors},
                                {nullptr, nullptr}};
    const luaL_Reg meta[] = {{"__tostring", robot_tostring},
                             {"__len", robot_len},
                             {"__eq", robot_eq},
                             {nullptr, nullptr}};
    register_type_with_fields<RobotPtr>(L, kRobotType, methods, robot_index, meta);

    const luaL_Reg group_methods[] = {
        {"drive", group_drive}, {"joints", group_joints}, {nullptr, nullptr}};
    const luaL_Reg group_meta[] = {{"__len", group_len}, {"__eq", group_eq}, {nullptr, nullptr}};
    register_type<GroupHandle>(L, kGroupType, group_methods, group_meta);

    // gaitlab.robot = { chain = ... }
    lua_newtable(L);
    lua_pushcfunction(L, robot_chain);
    lua_setfield(L, -2, "chain");
    lua_pushcfunction(L, robot_new);
    lua_setfield(L, -2, "new");
    lua_pushcfunction(L, robot_load);
    lua_setfield(L, -2, "load");
    lua_pushcfunction(L, robot_load_urdf);
    lua_setfield(L, -2, "load_urdf");
    lua_setfield(L, -2, "robot");
}

}  // namespace gaitlab::scripting
