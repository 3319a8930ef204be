// gaitlab.simulation: compile a world, step it, read its time.
#include <cmath>

#include <fmt/format.h>

#include "gaitlab/controller.h"
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
        auto world = to_world(L, -1);
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
        } else if (policy != "stop") {
            f.fail("on_controller_error", "'stop' or 'continue' expected, got '" + policy + "'");
        }
        const int rt = f.push("record");
        const bool records = !(rt == LUA_TNIL || (rt == LUA_TBOOLEAN && !lua_toboolean(L, -1)));
        lua_pop(L, 1);
        if (records) {
            f.fail("record",
                   "recording to a run folder is not available in this version "
                   "(use record = false)");
        }
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
            lua_pushstring(L, sim.options().on_controller_error == ControllerErrorPolicy::stop
                                  ? "stop"
                                  : "continue");
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
    const luaL_Reg methods[] = {{"run", simulation_run},
                                {"step", simulation_step},
                                {"reset", simulation_reset},
                                {"objects", simulation_objects},
                                {nullptr, nullptr}};
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
    lua_setfield(L, -2, "simulation");
}

}  // namespace gaitlab::scripting
