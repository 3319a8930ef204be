// gaitlab.simulation: compile a world, step it, read its time, record it.
#include <cmath>

#include <fmt/format.h>

#include "gaitlab/controller.h"
#include "hot_reload.h"
#include "lua_util.h"
#include "recording.h"
#include "scene.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

SimulationHandle& check_handle(lua_State* L, int index) {
    return check_object<SimulationHandle>(L, index, kSimulationType);
}

Simulation& check_sim(lua_State* L, int index) {
    return *check_handle(L, index).sim;
}

// record = false | true | "dir" | { dir =, record_every =, flush_seconds =, series = {...} }
// at `index`; errors are ArgErrors of argument `arg` (prefixed "field 'record': " in a table)
RecordRequest to_request(lua_State* L, int index, int arg, const std::string& prefix) {
    RecordRequest r;
    const int t = lua_type(L, index);
    auto fail = [&](const std::string& m) { throw ArgError(arg, prefix + m); };
    if (t == LUA_TNIL || t == LUA_TNONE) return r;
    if (t == LUA_TBOOLEAN) {
        r.mode = lua_toboolean(L, index) ? RecordRequest::Mode::on : RecordRequest::Mode::off;
        return r;
    }
    r.mode = RecordRequest::Mode::on;
    if (t == LUA_TSTRING) {
        r.dir = lua_tostring(L, index);
        if (r.dir.empty()) fail("run folder expected, got an empty string");
        return r;
    }
    if (t != LUA_TTABLE) {
        fail("false, true, a run folder or a table expected, got " + type_name(L, index));
    }
    try {
        Fields f(L, index, arg, {"dir", "record_every", "flush_seconds", "series"});
        r.dir = f.string("dir", "");
        const long long every = f.integer("record_every", 0);
        if (f.has("record_every") && every < 1) {
            fail(fmt::format("record_every must be at least 1 (got {})", every));
        }
        r.options.record_every = static_cast<int>(every);
        r.options.flush_seconds = f.number("flush_seconds", r.options.flush_seconds);
        if (!(std::isfinite(r.options.flush_seconds) && r.options.flush_seconds >= 0)) {
            fail("flush_seconds must be a non-negative number of seconds");
        }
        const int st = f.push("series");
        if (st == LUA_TTABLE) {
            const lua_Integer n = luaL_len(L, -1);
            for (lua_Integer i = 1; i <= n; ++i) {
                lua_rawgeti(L, -1, i);
                if (lua_type(L, -1) != LUA_TSTRING) {
                    lua_pop(L, 2);
                    fail("series: list of names, patterns or kinds expected");
                }
                r.options.series.emplace_back(lua_tostring(L, -1));
                lua_pop(L, 1);
            }
        } else if (st != LUA_TNIL) {
            const std::string tn = type_name(L, -1);
            lua_pop(L, 1);
            fail("series: list of names, patterns or kinds expected, got " + tn);
        }
        lua_pop(L, 1);

    } catch (const ArgError& e) {
        // the Fields helper's own messages ("unknown key ...") say which table
        const std::string m = e.what();
        if (!prefix.empty() && m.rfind(prefix, 0) != 0) throw ArgError(arg, prefix + m);
        throw;
    }
    return r;
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
        f.push("record");
        const RecordRequest request = to_request(L, -1, 1, "field 'record': ");
        lua_pop(L, 1);
        SimulationHandle* h = nullptr;
        try {
            validate(o);
            std::shared_ptr<Simulation> sim = world->compile(o);
            // the simulation lives in this Lua state: reporting through it is safe
            sim->set_controller_error_handler([L](const Controller& c, const std::exception& e) {
                std::string message = fmt::format("controller '{}' failed: {}", c.name(), e.what());
                const auto* se = dynamic_cast<const ScriptError*>(&e);
                if (se && !se->traceback().empty()) message += "\n" + se->traceback();
                report(L, message);
            });
            // controller files changed on disk are reloaded between ticks, at control ticks
            Simulation* raw = sim.get();
            sim->add_pre_tick([L, raw](Simulation&) {
                if (raw->ticks() % raw->options().control_every == 0) Reloader::of(L).poll(L);
            });
            h = new_object<SimulationHandle>(L, kSimulationType, SimulationHandle{sim, 0, {}});
        } catch (const SpecError& e) {
            throw ArgError(1, e.what());
        }
        try {
            Recordings::of(L).created(L, *h, request);
        } catch (const SpecError& e) {
            throw ArgError(1, std::string("field 'record': ") + e.what());
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

// sim:record(false | true | "dir" | { ... }): starts (or stops) recording now; returns the run
// folder, or nil if nothing records (gaitlab run --no-record)
int simulation_record(lua_State* L) {
    return protect(L, [&] {
        SimulationHandle& h = check_handle(L, 1);
        const RecordRequest r = to_request(L, 2, 2, "");
        if (r.mode == RecordRequest::Mode::off) {
            Recordings::of(L).stop(h);
            return 0;
        }
        std::string dir;
        try {
            dir = Recordings::of(L).start(L, h, r);
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        if (dir.empty()) {
            lua_pushnil(L);
        } else {
            lua_pushstring(L, dir.c_str());
        }
        return 1;
    });
}

// sim:flush(): writes what the recording holds in memory now
int simulation_flush(lua_State* L) {
    return protect(L, [&] {
        SimulationHandle& h = check_handle(L, 1);
        if (h.recorder) h.recorder->flush();
        return 0;
    });
}

int simulation_reset(lua_State* L) {
    return protect(L, [&] {
        check_sim(L, 1).reset();
        return 0;
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
        } else if (k == "record_dir") {
            const SimulationHandle& h = check_handle(L, 1);
            if (h.recorder && !h.recorder->closed()) {
                lua_pushstring(L, h.recorder->dir().c_str());
            } else {
                lua_pushnil(L);
            }
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
    const luaL_Reg methods[] = {{"run", simulation_run},     {"step", simulation_step},
                                {"reset", simulation_reset}, {"record", simulation_record},
                                {"flush", simulation_flush}, {"live", live_new},
                                {nullptr, nullptr}};
    luaL_newmetatable(L, kSimulationType);
    lua_newtable(L);
    luaL_setfuncs(L, methods, 0);
    lua_pushcclosure(L, simulation_index, 1);
    lua_setfield(L, -2, "__index");
    lua_pushcfunction(L, simulation_tostring);
    lua_setfield(L, -2, "__tostring");
    lua_pop(L, 1);
    register_type<SimulationHandle>(L, kSimulationType, nullptr);
    Recordings::install(L);

    lua_newtable(L);
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, simulation_new);
    lua_setfield(L, -2, "__call");
    lua_setmetatable(L, -2);
    lua_setfield(L, -2, "simulation");
}

}  // namespace gaitlab::scripting
