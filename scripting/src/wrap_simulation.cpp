// gaitlab.simulation: compile a world, step it, read its time.
#include <cmath>

#include <fmt/format.h>

#include "config_files.h"
#include "gaitlab/controller.h"
#include "gaitlab/files.h"
#include "hot_reload.h"
#include "lua_util.h"
#include "scene.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

using SimulationPtr = std::shared_ptr<Simulation>;

Simulation& check_sim(lua_State* L, int index) {
    return *check_object<SimulationPtr>(L, index, kSimulationType);
}

// registry table (weak keys): simulation userdata -> the world userdata it was compiled from
constexpr const char* kSimWorldsKey = "gaitlab.sim_worlds";

// compiles the world at `world_index` into a simulation with options `o` and pushes it; reports
// controller failures through the host and remembers the world (for sim:save)
void push_new_simulation(lua_State* L, int world_index, const SimulationOptions& o) {
    auto world = to_world(L, world_index);
    try {
        validate(o);
        SimulationPtr sim = world->compile(o);
        // the simulation lives in this Lua state: reporting through it is safe
        sim->set_controller_error_handler([L](const Controller& c, const std::exception& e) {
            std::string message = fmt::format("controller '{}' failed: {}", c.name(), e.what());
            const auto* se = dynamic_cast<const ScriptError*>(&e);
            if (se && !se->traceback().empty()) message += "\n" + se->traceback();
            report(L, message);
        });
        new_object<SimulationPtr>(L, kSimulationType, std::move(sim));
    } catch (const SpecError& e) {
        throw ArgError(1, e.what());
    }
    if (lua_getfield(L, LUA_REGISTRYINDEX, kSimWorldsKey) != LUA_TTABLE) {
        lua_pop(L, 1);
        lua_newtable(L);
        lua_createtable(L, 0, 1);
        lua_pushstring(L, "k");
        lua_setfield(L, -2, "__mode");
        lua_setmetatable(L, -2);
        lua_pushvalue(L, -1);
        lua_setfield(L, LUA_REGISTRYINDEX, kSimWorldsKey);
    }
    lua_pushvalue(L, -2);
    lua_pushvalue(L, world_index);
    lua_rawset(L, -3);
    lua_pop(L, 1);
}

int simulation_new(lua_State* L) {
    // called as gaitlab.simulation{...}: argument 1 is the gaitlab.simulation table itself
    return protect(L, [&] {
        Fields f(L, 2, 1,
                 {"world", "dt", "control_every", "record", "seed", "solver_iterations",
                  "on_controller_error"});
        if (f.push("world") == LUA_TNIL) f.fail("world", "gaitlab.World expected, got nil");
        if (!luaL_testudata(L, -1, kWorldType)) {
            f.fail("world", "gaitlab.World expected, got " + type_name(L, -1));
        }
        lua_pop(L, 1);
        SimulationOptions o;
        o.dt = f.number("dt", o.dt);
        o.control_every = static_cast<int>(f.integer("control_every", o.control_every));
        o.solver_iterations = static_cast<int>(f.integer("solver_iterations", o.solver_iterations));
        const long long seed = f.integer("seed", 0);
        if (seed < 0) f.fail("seed", "non-negative integer expected");
        o.seed = static_cast<std::uint64_t>(seed);
        const std::string policy = f.string("on_controller_error", "stop");
        if (policy == "continue") {
            o.on_controller_error = ControllerErrorPolicy::continue_;
        } else if (policy == "pause") {
            o.on_controller_error = ControllerErrorPolicy::pause;
        } else if (policy != "stop") {
            f.fail("on_controller_error",
                   "'stop', 'continue' or 'pause' expected, got '" + policy + "'");
        }
        const int rt = f.push("record");
        const bool records = !(rt == LUA_TNIL || (rt == LUA_TBOOLEAN && !lua_toboolean(L, -1)));
        lua_pop(L, 1);
        if (records) {
            f.fail("record",
                   "recording to a run folder is not available in this version "
                   "(use record = false)");
        }
        lua_getfield(L, 2, "world");
        push_new_simulation(L, lua_gettop(L), o);
        return 1;
    });
}

int simulation_run(lua_State* L) {
    return protect(L, [&] {
        Simulation& sim = check_sim(L, 1);
        const double seconds = check_number(L, 2);
        if (!(std::isfinite(seconds) && seconds >= 0)) {
            throw ArgError(2, "non-negative number of seconds expected");
        }
        sim.run(seconds);
        return 0;
    });
}

int simulation_step(lua_State* L) {
    return protect(L, [&] {
        Simulation& sim = check_sim(L, 1);
        const long long n = lua_isnoneornil(L, 2) ? 1 : check_integer(L, 2);
        if (n < 0) throw ArgError(2, "non-negative number of ticks expected");
        sim.step(static_cast<long>(n));
        return 0;
    });
}

// sim:save(path [, { duration = }]): writes the simulation file and its parts next to it
// (duration: how long `gaitlab run` runs it, default the time simulated so far, or 10 s); the
// path, or nil and a message
int simulation_save(lua_State* L) {
    return protect(L, [&] {
        Simulation& sim = check_sim(L, 1);
        const std::string path = script_path(L, check_string(L, 2));
        double duration = sim.time() > 0 ? sim.time() : 10;
        if (!lua_isnoneornil(L, 3)) {
            Fields f(L, 3, 3, {"duration"});
            duration = f.number("duration", duration);
            if (!(std::isfinite(duration) && duration >= 0)) {
                f.fail("duration", "non-negative number of seconds expected");
            }
        }
        lua_getfield(L, LUA_REGISTRYINDEX, kSimWorldsKey);
        lua_pushvalue(L, 1);
        lua_rawget(L, -2);
        auto world = to_world(L, -1);
        lua_pop(L, 2);
        return file_written(L, path,
                            [&] { save_simulation(path, *world, sim.options(), duration); });
    });
}

// gaitlab.simulation.load(path): the simulation a simulation file describes, and a table
// { name, duration, world, robots = { name = robot }, controllers = { name = { ctl, ... } },
// record = { enabled, dir, every, flush_seconds } }; or nil and a message
int simulation_load(lua_State* L) {
    return protect(L, [&] {
        const std::string path = script_path(L, check_string(L, 1));
        LoadedSimulation loaded;
        try {
            loaded = load_simulation(L, path);
        } catch (const FormatError& e) {
            lua_pushnil(L);
            lua_pushstring(L, e.what());
            return 2;
        }
        push_world(L, loaded.world);
        const int world = lua_gettop(L);
        try {
            push_new_simulation(L, world, loaded.file.options);
        } catch (const ArgError& e) {
            throw Error(fmt::format("{}: {}", path, e.what()));
        }
        lua_createtable(L, 0, 6);
        lua_pushstring(L, loaded.file.name.c_str());
        lua_setfield(L, -2, "name");
        lua_pushnumber(L, loaded.file.duration);
        lua_setfield(L, -2, "duration");
        lua_pushvalue(L, world);
        lua_setfield(L, -2, "world");
        lua_newtable(L);
        lua_newtable(L);
        for (size_t r = 0; r < loaded.robots.size(); ++r) {
            const std::string& name = loaded.robots[r]->spec.name;
            push_robot(L, loaded.robots[r]);
            lua_setfield(L, -3, name.c_str());
            lua_createtable(L, static_cast<int>(loaded.controllers[r].size()), 0);
            for (size_t c = 0; c < loaded.controllers[r].size(); ++c) {
                push_controller(L, loaded.controllers[r][c], true);
                lua_rawseti(L, -2, static_cast<lua_Integer>(c + 1));
            }
            lua_setfield(L, -2, name.c_str());
        }
        lua_setfield(L, -3, "controllers");
        lua_setfield(L, -2, "robots");
        const RecordSpec& rec = loaded.file.record;
        lua_createtable(L, 0, 4);
        lua_pushboolean(L, rec.enabled);
        lua_setfield(L, -2, "enabled");
        lua_pushstring(L, rec.dir.c_str());
        lua_setfield(L, -2, "dir");
        lua_pushinteger(L, rec.every);
        lua_setfield(L, -2, "every");
        lua_pushnumber(L, rec.flush_seconds);
        lua_setfield(L, -2, "flush_seconds");
        lua_setfield(L, -2, "record");
        return 2;
    });
}

int simulation_reset(lua_State* L) {
    return protect(L, [&] {
        check_sim(L, 1).reset();
        return 0;
    });
}

// sim:objects(): the world's dynamic objects (boxes, then cylinders, with mass > 0) as
// { object = "box 2", position =, orientation =, velocity = }
int simulation_objects(lua_State* L) {
    return protect(L, [&] {
        Simulation& sim = check_sim(L, 1);
        std::vector<std::string> names;
        const WorldSpec& w = sim.world();
        for (size_t i = 0; i < w.boxes.size(); ++i) {
            if (w.boxes[i].mass > 0) names.push_back(fmt::format("box {}", i + 1));
        }
        for (size_t i = 0; i < w.cylinders.size(); ++i) {
            if (w.cylinders[i].mass > 0) names.push_back(fmt::format("cylinder {}", i + 1));
        }
        lua_createtable(L, static_cast<int>(names.size()), 0);
        for (size_t k = 0; k < names.size(); ++k) {
            const BodyState s = sim.object(static_cast<int>(k));
            lua_createtable(L, 0, 4);
            lua_pushstring(L, names[k].c_str());
            lua_setfield(L, -2, "object");
            push_vec3(L, s.pose.position);
            lua_setfield(L, -2, "position");
            push_quat(L, s.pose.orientation);
            lua_setfield(L, -2, "orientation");
            push_vec3(L, s.linear_velocity);
            lua_setfield(L, -2, "velocity");
            lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
        }
        return 1;
    });
}

int simulation_index(lua_State* L) {
    return protect(L, [&] {
        Simulation& sim = check_sim(L, 1);
        const char* key = lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : "";
        const std::string k = key;
        if (k == "time") {
            lua_pushnumber(L, sim.time());
        } else if (k == "ticks") {
            lua_pushinteger(L, sim.ticks());
        } else if (k == "dt") {
            lua_pushnumber(L, sim.options().dt);
        } else if (k == "control_every") {
            lua_pushinteger(L, sim.options().control_every);
        } else if (k == "solver_iterations") {
            lua_pushinteger(L, sim.options().solver_iterations);
        } else if (k == "on_controller_error") {
            lua_pushstring(L, to_string(sim.options().on_controller_error));
        } else if (k == "paused") {
            lua_pushboolean(L, sim.paused());
        } else if (k == "seed") {
            lua_pushinteger(L, static_cast<lua_Integer>(sim.options().seed));
        } else {
            lua_getfield(L, lua_upvalueindex(1), key);
        }
        return 1;
    });
}

int simulation_tostring(lua_State* L) {
    return protect(L, [&] {
        Simulation& sim = check_sim(L, 1);
        lua_pushfstring(L, "gaitlab.Simulation (t = %f s, robots: %d)", sim.time(),
                        sim.robot_count());
        return 1;
    });
}

}  // namespace

void open_simulation(lua_State* L) {
    const luaL_Reg methods[] = {{"run", simulation_run},         {"step", simulation_step},
                                {"reset", simulation_reset},     {"save", simulation_save},
                                {"objects", simulation_objects}, {nullptr, nullptr}};
    luaL_newmetatable(L, kSimulationType);
    lua_newtable(L);
    luaL_setfuncs(L, methods, 0);
    lua_pushcclosure(L, simulation_index, 1);
    lua_setfield(L, -2, "__index");
    lua_pushcfunction(L, simulation_tostring);
    lua_setfield(L, -2, "__tostring");
    lua_pop(L, 1);
    register_type<SimulationPtr>(L, kSimulationType, nullptr);

    lua_newtable(L);
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, simulation_new);
    lua_setfield(L, -2, "__call");
    lua_setmetatable(L, -2);
    lua_pushcfunction(L, simulation_load);
    lua_setfield(L, -2, "load");
    lua_setfield(L, -2, "simulation");
}

}  // namespace gaitlab::scripting
