// gaitlab.world: gravity, floor, boxes, and placing robots.
#include <fmt/format.h>

#include "gaitlab/files.h"
#include "gaitlab/xml.h"
#include "lua_util.h"
#include "scene.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

using WorldPtr = std::shared_ptr<WorldBinding>;

Quat yaw_rotation(double deg) {
    return Quat::from_axis_angle({0, 0, 1}, deg_to_rad(deg));
}

int world_new(lua_State* L) {
    // called as gaitlab.world{...}: argument 1 is the gaitlab.world table itself
    return protect(L, [&] {
        auto world = std::make_shared<WorldBinding>();
        if (!lua_isnoneornil(L, 2)) {
            Fields f(L, 2, 1, {"floor", "gravity"});
            world->spec.gravity = f.vec3("gravity", world->spec.gravity);
            const int t = f.push("floor");
            if (t == LUA_TBOOLEAN) {
                world->spec.floor.enabled = lua_toboolean(L, -1);
            } else if (t == LUA_TTABLE) {
                Fields floor(L, -1, 1, {"friction"});
                world->spec.floor.friction = floor.number("friction", 1.0);
            } else if (t != LUA_TNIL) {
                f.fail("floor", "table or boolean expected, got " + type_name(L, -1));
            }
            lua_pop(L, 1);
        }
        try {
            validate(world->spec);
        } catch (const SpecError& e) {
            throw ArgError(1, e.what());
        }
        push_world(L, std::move(world));
        return 1;
    });
}

int world_add(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = *check_object<WorldPtr>(L, 1, kWorldType);
        auto robot = to_robot(L, 2);
        if (robot->in_world) {
            throw ArgError(2, "robot '" + robot->spec.name + "' is already in a world");
        }
        // the robot frame has its tail at the origin and the floor at z = 0; without a pose the
        // world's placement for the robot's name (from an environment file) applies
        std::optional<Pose> pose;
        if (!lua_isnoneornil(L, 3)) {
            Fields f(L, 3, 3, {"x", "y", "z", "yaw"});
            pose = Pose{{f.number("x", 0), f.number("y", 0), f.number("z", 0)},
                        yaw_rotation(f.number("yaw", 0))};
        }
        w.add(robot, pose);
        lua_settop(L, 1);
        return 1;
    });
}

int world_box(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = *check_object<WorldPtr>(L, 1, kWorldType);
        Fields f(L, 2, 2, {"size", "position", "yaw", "mass", "friction"});
        BoxSpec box;
        box.size = f.vec3("size", box.size);
        box.pose.position = f.vec3("position", {0, 0, box.size.z / 2});
        box.pose.orientation = yaw_rotation(f.number("yaw", 0));
        box.mass = f.number("mass", 0);
        box.friction = f.number("friction", 1.0);
        // validated among the world's boxes, so the message numbers it as the world does
        WorldSpec probe;
        probe.boxes = w.spec.boxes;
        probe.boxes.push_back(box);
        try {
            validate(probe);
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        w.spec.boxes.push_back(box);
        lua_settop(L, 1);
        return 1;
    });
}

// gaitlab.world.load(path): a world from an environment file (objects, and where robots of
// the names it places go when added), or nil and a message
int world_load(lua_State* L) {
    return protect(L, [&] {
        const std::string path = script_path(L, check_string(L, 1));
        return file_read(L, [&] {
            EnvironmentSpec env = read_environment(path);
            auto world = std::make_shared<WorldBinding>();
            world->spec = std::move(env.world);
            world->placements = std::move(env.placements);
            push_world(L, std::move(world));
        });
    });
}

// world:save(path): writes the environment file, with where its robots are; the path, or nil
// and a message
int world_save(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = *check_object<WorldPtr>(L, 1, kWorldType);
        const std::string path = script_path(L, check_string(L, 2));
        EnvironmentSpec env;
        env.world = w.spec;
        for (const WorldBinding::Entry& e : w.robots) {
            for (const Placement& p : env.placements) {
                if (p.robot == e.robot->spec.name) {
                    throw Error(
                        fmt::format("two robots are named '{}': give each its own name "
                                    "to save where they are",
                                    p.robot));
                }
            }
            env.placements.push_back({e.robot->spec.name, e.pose});
        }
        return file_written(L, path, [&] { write_environment(path, env); });
    });
}

int world_tostring(lua_State* L) {
    return protect(L, [&] {
        WorldBinding& w = *check_object<WorldPtr>(L, 1, kWorldType);
        lua_pushfstring(L, "gaitlab.World (%d robots, %d boxes)", static_cast<int>(w.robots.size()),
                        static_cast<int>(w.spec.boxes.size()));
        return 1;
    });
}

}  // namespace

void push_world(lua_State* L, std::shared_ptr<WorldBinding> world) {
    new_object<WorldPtr>(L, kWorldType, std::move(world));
}

std::shared_ptr<WorldBinding> to_world(lua_State* L, int index) {
    return check_object<WorldPtr>(L, index, kWorldType);
}

void open_world(lua_State* L) {
    const luaL_Reg methods[] = {
        {"add", world_add}, {"box", world_box}, {"save", world_save}, {nullptr, nullptr}};
    const luaL_Reg meta[] = {{"__tostring", world_tostring}, {nullptr, nullptr}};
    register_type<WorldPtr>(L, kWorldType, methods, meta);

    // gaitlab.world is a table (for future members) that is called to make a world
    lua_newtable(L);
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, world_new);
    lua_setfield(L, -2, "__call");
    lua_setmetatable(L, -2);
    lua_pushcfunction(L, world_load);
    lua_setfield(L, -2, "load");
    lua_setfield(L, -2, "world");
}

}  // namespace gaitlab::scripting
