// gaitlab.simulation: compile a world, step it, read its time, record it.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <new>
#include <optional>

#include <fmt/format.h>

#include "config_files.h"
#include "gaitlab/accuracy.h"
#include "gaitlab/checked.h"
#include "gaitlab/controller.h"
#include "gaitlab/files.h"
#include "gaitlab/suggest.h"
#include "guard.h"
#include "hot_reload.h"
#include "lua_util.h"
#include "playback.h"
#include "recording.h"
#include "scene.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

SimulationHandle& check_handle(lua_State* L, int index) {
    return check_object<SimulationHandle>(L, index, kSimulationType);
}

// the simulation of the handle at `index`, kept alive for the caller: stepping it runs Lua
// code, which could let the handle go (its __gc, through the debug library)
std::shared_ptr<Simulation> check_sim(lua_State* L, int index) {
    return check_handle(L, index).sim;
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
        r.dir = to_string(L, index);
        if (r.dir.empty()) fail("run folder expected, got an empty string");
        return r;
    }
    if (t != LUA_TTABLE) {
        fail("false, true, a run folder or a table expected, got " + type_name(L, index));
    }
    try {
        Fields f(L, index, arg,
                 {"enabled", "dir", "every", "record_every", "flush_seconds", "series"});
        // enabled = false: as record = false (a simulation file's <record enabled="false">)
        if (!f.boolean("enabled", true)) r.mode = RecordRequest::Mode::off;
        r.dir = f.string("dir", "");
        if (f.has("every") && f.has("record_every")) {
            f.fail("every", "give 'every' or 'record_every', not both");
        }
        // every: as a simulation file's <record every> (0: the control period)
        if (f.has("every")) {
            try {
                r.options.record_every =
                    checked_int("every", f.integer("every", 0), 0, kMaxControlEvery);
            } catch (const SpecError& e) {
                fail(e.what());
            }
        }
        if (f.has("record_every")) {
            try {
                r.options.record_every =
                    checked_int("record_every", f.integer("record_every", 0), 1, kMaxControlEvery);
            } catch (const SpecError& e) {
                fail(e.what());
            }
        }
        r.options.flush_seconds = f.number("flush_seconds", r.options.flush_seconds);
        if (!(std::isfinite(r.options.flush_seconds) && r.options.flush_seconds >= 0)) {
            fail("flush_seconds must be a non-negative number of seconds");
        }
        const int st = f.push("series");
        if (st == LUA_TTABLE) {
            const auto n = static_cast<lua_Integer>(lua_rawlen(L, -1));
            for (lua_Integer i = 1; i <= n; ++i) {
                lua_rawgeti(L, -1, i);
                if (lua_type(L, -1) != LUA_TSTRING) {
                    lua_pop(L, 2);
                    fail("series: list of names, patterns or kinds expected");
                }
                r.options.series.emplace_back(to_string(L, -1));
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

// compiles `world` into a simulation with options `o` and pushes it: reports controller
// failures through the host, reloads changed controller files between ticks, and records as
// `request` and the host say
void push_simulation(lua_State* L, std::shared_ptr<Simulation> sim,
                     std::shared_ptr<WorldBinding> world, const RecordRequest& request);

void push_new_simulation(lua_State* L, std::shared_ptr<WorldBinding> world,
                         const SimulationOptions& o, const RecordRequest& request) {
    std::shared_ptr<Simulation> sim;
    try {
        validate(o);
        sim = world->compile(o);
    } catch (const SpecError& e) {
        throw ArgError(1, e.what());
    } catch (const std::bad_alloc&) {
        // the world's spec is copied before the simulation builds (which says so itself)
        throw Error("not enough memory to build the simulation");
    }
    for (const std::string& w : sim->warnings())
        report(main_thread(L), "warning: " + w);
    // the world's robot handles become this simulation's only once its handle is made (a
    // recording refused on the way leaves them, and their controllers, as they were)
    const std::shared_ptr<WorldBinding> linked = world;
    push_simulation(L, sim, std::move(world), request);
    linked->link(sim);
}

// pushes a handle for `sim` (new, or a clone), made from `world`: reports controller failures
// through the host, reloads changed controller files between ticks, and records as `request`
// and the host say
void push_simulation(lua_State* L, std::shared_ptr<Simulation> sim,
                     std::shared_ptr<WorldBinding> world, const RecordRequest& request) {
    SimulationHandle* h = nullptr;
    lua_State* main = main_thread(L);
    try {
        // the simulation lives in this Lua state: reporting through it is safe
        sim->set_controller_error_handler([main](const Controller& c, const std::exception& e) {
            std::string message = fmt::format("controller '{}' failed: {}", c.name(), e.what());
            const auto* se = dynamic_cast<const ScriptError*>(&e);
            if (se && !se->traceback().empty()) message += "\n" + se->traceback();
            report(main, message);
        });
        // a warning found running (a robot passing through itself), as compiling's are
        sim->set_warning_handler([main](const std::string& w) { report(main, "warning: " + w); });
        // between ticks: an interrupt (Ctrl-C, a signal) stops the run; controller files
        // changed on disk are reloaded, at control ticks
        Simulation* raw = sim.get();
        Guard* guard = &Guard::of(L);
        sim->add_pre_tick([main, raw, guard](Simulation&) {
            if (guard->interrupted() != 0) throw Error(guard->interrupt_message());
            if (raw->ticks() % raw->options().control_every == 0) Reloader::of(main).poll(main);
        });
        auto player = std::make_shared<Player>(sim);
        h = new_object<SimulationHandle>(
            L, kSimulationType,
            SimulationHandle{sim, 0, {}, std::move(world), std::move(player), {}, {}, {}, {}});
    } catch (const SpecError& e) {
        throw ArgError(1, e.what());
    } catch (const std::bad_alloc&) {
        // the world's spec is copied before the simulation builds (which says so itself)
        throw Error("not enough memory to build the simulation");
    }
    const int at = lua_gettop(L);  // the handle
    try {
        try {
            Recordings::of(L).created(L, *h, request);
        } catch (...) {
            // a recording refused: the handle goes now, not when the collector finds it, so
            // the simulation lets its controllers go (the next one binds them, not copies)
            h->~SimulationHandle();
            lua_settop(L, at);
            lua_pushnil(L);
            lua_setmetatable(L, at);
            throw;
        }
    } catch (const SpecError& e) {
        throw ArgError(1, std::string("field 'record': ") + e.what());
    }
    for (const auto& fn : Playback::of(L).on_player)
        fn(h->player, h->index);
}

// runs `ticks` ticks of the handle's simulation for sim:run and sim:step: at once, or through
// the host's runner (a viewer paces them)
long run_ticks(lua_State* L, const SimulationHandle& h, long ticks) {
    const Playback& playback = Playback::of(L);
    if (!playback.runner) return h.sim->step(ticks);
    h.sim->step(0);  // from inside its own tick: refused as a step would be
    const std::shared_ptr<Player> player = h.player;
    return playback.runner(*player, h.index, ticks);
}

// run_ticks for sim:run and sim:step, stopped by Ctrl-C in an interpreter (InterruptScope).
// gaitlab raises that interrupt itself: the recordings end "interrupted" (naming the signal)
// now, as in gaitlab run, rather than "finished" when the interpreter closes the state
void run_interruptible(lua_State* L, const SimulationHandle& h, long ticks) {
    const InterruptScope interruptible(L);  // Ctrl-C in an interpreter (guard.h)
    try {
        run_ticks(L, h, ticks);
    } catch (...) {
        const Guard& guard = Guard::of(L);
        if (guard.owner() == StateOwner::interpreter && guard.interrupted() != 0) {
            try {
                Recordings::of(L).finish("");
            } catch (const std::exception& e) {
                report(main_thread(L), e.what());  // the interrupt stays the error
            }
        }
        throw;
    }
}

// the keys of the settings a simulation steps with, read from `f` (table argument `arg`) into
// `o`; keys not given keep o's values (newton_steps: the world's choice where o's is automatic)
void read_settings(Fields& f, int arg, SimulationOptions& o) {
    o.dt = f.number("dt", o.dt);
    // counts are checked before they become ints: 2^32 + 30 must not become 30
    const long long every = f.integer("control_every", o.control_every);
    const long long iterations = f.integer("solver_iterations", o.solver_iterations);
    const long long newton = f.integer("newton_steps", o.newton_steps);
    try {
        o.control_every = checked_int("control_every", every, 1, kMaxControlEvery);
        o.solver_iterations = checked_int("solver_iterations", iterations, 1, kMaxSolverIterations);
        if (f.has("newton_steps"))
            o.newton_steps = checked_int("newton_steps", newton, 0, kMaxNewtonSteps);
    } catch (const SpecError& e) {
        throw ArgError(arg, e.what());
    }
    const std::string solver = f.string("solver", to_string(o.solver));
    if (!parse_solver(solver, o.solver)) {
        f.fail("solver", solver_names() + " expected, got '" + solver + "'");
    }
}

int simulation_new(lua_State* L) {
    // called as gaitlab.simulation{...}: argument 1 is the gaitlab.simulation table itself
    return protect(L, [&] {
        Fields f(L, 2, 1,
                 {"world", "name", "duration", "dt", "control_every", "record", "seed",
                  "solver_iterations", "solver", "newton_steps", "on_controller_error"});
        // name and duration: what sim:save writes (a simulation file's name and duration)
        SimulationFile file;
        file.name = f.string("name", file.name);
        if (file.name.empty()) f.fail("name", "a non-empty name expected");
        try {
            validate_name("simulation name", file.name);
        } catch (const SpecError& e) {
            f.fail("name", e.what());
        }
        file.duration = f.number("duration", file.duration);
        if (!(std::isfinite(file.duration) && file.duration >= 0)) {
            f.fail("duration", "non-negative number of seconds expected");
        }
        if (f.push("world") == LUA_TNIL) f.fail("world", "gaitlab.World expected, got nil");
        if (!luaL_testudata(L, -1, kWorldType)) {
            f.fail("world", "gaitlab.World expected, got " + type_name(L, -1));
        }
        lua_pop(L, 1);
        SimulationOptions o;
        // newton_steps not given: the simulation chooses for its world (automatic_newton_steps)
        read_settings(f, 1, o);
        try {
            // as a simulation file's duration: a run of round(duration / dt) ticks must fit
            if (f.has("duration")) checked_ticks("duration", file.duration, o.dt);
        } catch (const SpecError& e) {
            throw ArgError(1, e.what());
        }
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
        f.push("record");
        const RecordRequest request = to_request(L, -1, 1, "field 'record': ");
        lua_pop(L, 1);
        const bool has_duration = f.has("duration");
        if (request.mode != RecordRequest::Mode::absent) {
            file.record.enabled = request.mode == RecordRequest::Mode::on;
        }
        file.record.dir = request.dir;
        file.record.every = request.options.record_every;
        file.record.flush_seconds = request.options.flush_seconds;
        raw_getfield(L, 2, "world");
        push_new_simulation(L, to_world(L, -1), o, request);
        SimulationHandle& h = check_handle(L, -1);
        if (f.has("name")) h.name = file.name;
        if (has_duration) h.duration = file.duration;
        h.record = file.record;
        return 1;
    });
}

int simulation_run(lua_State* L) {
    return protect(L, [&] {
        const std::shared_ptr<Simulation> kept = check_sim(L, 1);
        Simulation& sim = *kept;
        const double seconds = check_number(L, 2);
        if (!(std::isfinite(seconds) && seconds >= 0)) {
            throw ArgError(2, "non-negative number of seconds expected");
        }
        try {
            sim.ticks_for(seconds);  // a run that would not fit is a bad argument
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        sim.run(0);  // from inside its own tick: refused, naming run (run_ticks steps)
        const ProgressScope progress(L, sim, sim.time() + seconds);
        run_interruptible(L, check_handle(L, 1), sim.ticks_for(seconds));
        return 0;
    });
}

int simulation_step(lua_State* L) {
    return protect(L, [&] {
        const std::shared_ptr<Simulation> kept = check_sim(L, 1);
        Simulation& sim = *kept;
        const long long n = lua_isnoneornil(L, 2) ? 1 : check_integer(L, 2);
        if (n < 0) throw ArgError(2, "non-negative number of ticks expected");
        try {
            checked_integer("ticks", n, 0, kMaxTicks - sim.ticks());
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        const double end = static_cast<double>(sim.ticks() + n) * sim.options().dt;
        const ProgressScope progress(L, sim, end);
        run_interruptible(L, check_handle(L, 1), static_cast<long>(n));
        return 0;
    });
}

// the handle of robot `r` of the handle's simulation: the world's while the simulation is the
// newest its world built (the world's handle is that one's robot), else one of its own
std::shared_ptr<RobotBinding> robot_handle(SimulationHandle& h, int r) {
    const std::shared_ptr<Simulation>& sim = h.sim;
    if (h.world && static_cast<size_t>(r) < h.world->robots.size()) {
        const std::shared_ptr<RobotBinding>& own = h.world->robots[static_cast<size_t>(r)].robot;
        if (own->sim.lock() == sim && own->index == r && drives_of(*own, *sim, r)) return own;
    }
    h.robots.resize(static_cast<size_t>(sim->robot_count()));
    std::shared_ptr<RobotBinding>& mine = h.robots[static_cast<size_t>(r)];
    if (!mine || !drives_of(*mine, *sim, r)) mine = robot_of(sim, r);
    return mine;
}

// sim:save(path [, { duration = }]): writes the simulation file and its parts next to it
// (duration: how long `gaitlab run` runs it, default the time simulated so far, or 10 s); the
// path, or nil and a message
int simulation_save(lua_State* L) {
    return protect(L, [&] {
        SimulationHandle& h = check_handle(L, 1);
        const Simulation& sim = *h.sim;
        const ScriptPath path(L, check_string(L, 2));
        double duration = h.duration ? *h.duration : sim.time() > 0 ? sim.time() : 10;
        if (!lua_isnoneornil(L, 3)) {
            Fields f(L, 3, 3, {"duration"});
            duration = f.number("duration", duration);
            if (!(std::isfinite(duration) && duration >= 0)) {
                f.fail("duration", "non-negative number of seconds expected");
            }
        }
        // the world as this simulation has it: its objects and robots as built, with the
        // controllers and sensors they have here, not what the world (from which a script may
        // build more) holds now, nor the world's robot handles, which stand for the newest
        const std::shared_ptr<WorldBinding> world = WorldBinding::of(h.sim, *h.world);
        return file_written(L, path, [&] {
            save_simulation(path.path(), *world, sim.written_options(), duration, h.name, h.record);
        });
    });
}

// gaitlab.simulation.load(path): the simulation a simulation file describes, and a table
// { name, duration, world, robots = { name = robot }, controllers = { name = { ctl, ... } },
// record = { enabled, dir, every, flush_seconds } }; or nil and a message
int simulation_load(lua_State* L) {
    return protect(L, [&] {
        // absolute: the parts are resolved against it, and a path relative to a script in a
        // relative folder ("proj/run.lua") would be resolved against that folder twice
        const std::string path = std::filesystem::absolute(script_path(L, check_string(L, 1)))
                                     .lexically_normal()
                                     .string();
        LoadedSimulation loaded;
        std::optional<std::string> unreadable;
        try {
            loaded = load_simulation(L, path);
        } catch (const FormatError& e) {
            unreadable = e.what();
        }
        if (unreadable) return push_fail(L, *unreadable);
        push_world(L, loaded.world);
        const int world = lua_gettop(L);
        // the file's <record> applies as `record = ...` would
        const RecordSpec& rec = loaded.file.record;
        RecordRequest request;
        if (rec.enabled) {
            request.mode = *rec.enabled ? RecordRequest::Mode::on : RecordRequest::Mode::off;
        }
        request.dir = rec.dir.empty() ? "" : resolve_path(path, rec.dir);
        request.options.record_every = rec.every;
        request.options.flush_seconds = rec.flush_seconds;
        // what goes wrong while the file's simulation is built is the file's: named at its
        // <simulation> line, as nil and a message like any other problem of the file
        std::string failed;
        try {
            push_new_simulation(L, loaded.world, loaded.file.options, request);
        } catch (const ScriptError&) {
            throw;  // names its own Lua file and line
        } catch (const std::exception& e) {
            failed = fmt::format("{}:{}: {}", path, loaded.file.line, e.what());
        }
        if (!failed.empty()) {
            lua_settop(L, world - 1);
            return push_fail(L, failed);
        }
        {
            // saved again, it keeps the file's name, duration and <record>
            SimulationHandle& made = check_handle(L, -1);
            made.name = loaded.file.name;
            made.duration = loaded.file.duration;
            made.record = rec;
        }
        lua_createtable(L, 0, 7);
        lua_pushinteger(L, loaded.file.line);
        lua_setfield(L, -2, "line");
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
        lua_createtable(L, 0, 4);
        if (rec.enabled) {
            lua_pushboolean(L, *rec.enabled);
            lua_setfield(L, -2, "enabled");
        }
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

// sim:play(): plays the simulation against the wall clock (LuaHost::pump steps it)
int simulation_play(lua_State* L) {
    return protect(L, [&] {
        Playback::of(L).play(check_handle(L, 1));
        return 0;
    });
}

int simulation_pause(lua_State* L) {
    return protect(L, [&] {
        check_handle(L, 1).player->pause();
        return 0;
    });
}

// a number as messages show it: "nan" whatever its sign bit
std::string number_text(double v) {
    return std::isnan(v) ? "nan" : fmt::format("{}", v);
}

// pushes a number, or nil for NaN (a measure not made yet)
void push_measure(lua_State* L, double v) {
    if (std::isnan(v)) {
        lua_pushnil(L);
    } else {
        lua_pushnumber(L, v);
    }
}

// sim:status(): { simulation, time, ticks, playing, speed, delay, factor, failure,
// controllers = { { name, robot, joints, state, error, params = { { name, value, unit } } } },
// robots = { { name, position, heading, turned } } }, which prints as a few lines of text
// (stdlib/simulation.lua)
int simulation_status(lua_State* L) {
    return protect(L, [&] {
        const SimulationHandle& h = check_handle(L, 1);
        const std::shared_ptr<Simulation> kept = h.sim;
        const Simulation& sim = *kept;
        const Player& p = *h.player;
        lua_createtable(L, 0, 10);
        lua_pushinteger(L, h.index);
        lua_setfield(L, -2, "simulation");
        lua_pushnumber(L, sim.time());
        lua_setfield(L, -2, "time");
        lua_pushinteger(L, sim.ticks());
        lua_setfield(L, -2, "ticks");
        lua_pushboolean(L, p.playing());
        lua_setfield(L, -2, "playing");
        lua_pushnumber(L, p.speed());
        lua_setfield(L, -2, "speed");
        lua_pushnumber(L, p.delay());
        lua_setfield(L, -2, "delay");
        push_measure(L, p.measured_speed());
        lua_setfield(L, -2, "factor");
        if (!p.failure().empty()) {
            lua_pushstring(L, p.failure().c_str());
            lua_setfield(L, -2, "failure");
        }
        lua_createtable(L, sim.drive_count(), 0);
        for (int d = 0; d < sim.drive_count(); ++d) {
            const Controller& c = sim.controller(d);
            lua_createtable(L, 0, 6);
            lua_pushstring(L, sim.drive_label(d).c_str());
            lua_setfield(L, -2, "name");
            lua_pushstring(L, sim.robot_label(sim.drive_robot(d)).c_str());
            lua_setfield(L, -2, "robot");
            const std::vector<int>& joints = sim.drive_joints(d);
            lua_createtable(L, static_cast<int>(joints.size()), 0);
            for (size_t j = 0; j < joints.size(); ++j) {
                lua_pushinteger(L, joints[j] + 1);
                lua_rawseti(L, -2, static_cast<lua_Integer>(j + 1));
            }
            lua_setfield(L, -2, "joints");
            lua_pushstring(L, c.failed() ? "failed" : "running");
            lua_setfield(L, -2, "state");
            if (c.failed()) {
                lua_pushstring(L, c.failure().c_str());
                lua_setfield(L, -2, "error");
            }
            const std::vector<ParamDef>& params = c.def().params;
            lua_createtable(L, static_cast<int>(params.size()), 0);
            for (size_t i = 0; i < params.size(); ++i) {
                lua_createtable(L, 0, 3);
                lua_pushstring(L, params[i].name.c_str());
                lua_setfield(L, -2, "name");
                lua_pushnumber(L, c.param(static_cast<int>(i)));
                lua_setfield(L, -2, "value");
                lua_pushstring(L, params[i].unit.c_str());
                lua_setfield(L, -2, "unit");
                lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
            }
            lua_setfield(L, -2, "params");
            lua_rawseti(L, -2, d + 1);
        }
        lua_setfield(L, -2, "controllers");
        lua_createtable(L, sim.robot_count(), 0);
        for (int r = 0; r < sim.robot_count(); ++r) {
            lua_createtable(L, 0, 5);
            lua_pushstring(L, sim.robot_label(r).c_str());
            lua_setfield(L, -2, "name");
            push_vec3(L, sim.robot_position(r));
            lua_setfield(L, -2, "position");
            lua_pushnumber(L, rad_to_deg(sim.robot_heading(r)));
            lua_setfield(L, -2, "heading");
            lua_pushnumber(L, rad_to_deg(sim.robot_turned(r)));
            lua_setfield(L, -2, "turned");
            lua_pushnumber(L, sim.robot_energy(r));
            lua_setfield(L, -2, "energy");
            lua_rawseti(L, -2, r + 1);
        }
        lua_setfield(L, -2, "robots");
        // stdlib/simulation.lua registers how a status prints
        luaL_setmetatable(L, "gaitlab.Status");
        return 1;
    });
}

// sim.speed = x, sim.delay = x; every other field is read-only
int simulation_newindex(lua_State* L) {
    return protect(L, [&] {
        SimulationHandle& h = check_handle(L, 1);
        const std::string key = lua_type(L, 2) == LUA_TSTRING ? to_string(L, 2) : "";
        const bool speed = key == "speed";
        if (speed || key == "delay") {
            int ok = 0;
            const double v = lua_tonumberx(L, 3, &ok);
            if (!ok) {
                throw Error(fmt::format("sim.{}: number expected, got {}", key, type_name(L, 3)));
            }
            if (speed && !(v > 0)) {
                throw Error(fmt::format(
                    "sim.speed: a real-time factor > 0 expected (math.huge: as fast as possible), "
                    "got {}",
                    number_text(v)));
            }
            if (!speed && !(v >= 0 && v <= kMaxPlayDelay)) {
                throw Error(fmt::format("sim.delay: seconds in [0, {:g}] expected, got {}",
                                        kMaxPlayDelay, number_text(v)));
            }
            if (speed) {
                h.player->set_speed(v);
            } else {
                h.player->set_delay(v);
            }
            return 0;
        }
        if (key == "playing") {
            throw Error("sim.playing is read-only: call sim:play() or sim:pause()");
        }
        const std::string what =
            key.empty() ? "a " + type_name(L, 2) + " key" : "field '" + key + "'";
        throw Error(fmt::format(
            "cannot set {} of a gaitlab.Simulation (only speed and delay can be set)", what));
    });
}

// sim:clone([{ record =, dt =, control_every =, solver_iterations =, solver =, newton_steps =
// }]): an independent copy of the simulation as it stands, whose future is bit-identical to
// the original's (Simulation::clone), or which steps on with the settings given
// (Simulation::clone(settings)); not recorded unless `record` says
int simulation_clone(lua_State* L) {
    return protect(L, [&] {
        SimulationHandle& h = check_handle(L, 1);
        RecordRequest request;
        request.mode = RecordRequest::Mode::off;
        SimulationOptions settings = h.sim->options();
        bool other = false;
        if (!lua_isnoneornil(L, 2)) {
            Fields f(
                L, 2, 2,
                {"record", "dt", "control_every", "solver_iterations", "solver", "newton_steps"});
            if (f.push("record") != LUA_TNIL) request = to_request(L, -1, 2, "field 'record': ");
            lua_pop(L, 1);
            for (const char* key :
                 {"dt", "control_every", "solver_iterations", "solver", "newton_steps"})
                other = other || f.has(key);
            read_settings(f, 2, settings);
        }
        const std::shared_ptr<Simulation> kept = h.sim;
        const std::shared_ptr<WorldBinding> world = h.world;
        std::shared_ptr<Simulation> copy(other ? kept->clone(settings) : kept->clone());
        // what the copy's own settings are warned of, as a new simulation's are
        const std::vector<std::string>& had = kept->warnings();
        for (const std::string& w : copy->warnings()) {
            if (std::find(had.begin(), had.end(), w) == had.end())
                report(main_thread(L), "warning: " + w);
        }
        const std::string name = h.name;
        const std::optional<double> duration = h.duration;
        const RecordSpec record = h.record;
        push_simulation(L, copy, WorldBinding::of(copy, *world), request);
        SimulationHandle& made = check_handle(L, -1);
        made.name = name;
        made.duration = duration;
        made.record = record;
        return 1;
    });
}

// sim:check_accuracy([{ seconds =, cycle =, settle = }]): the world of this simulation run
// again from time 0 for `seconds` (default 20) at its options, at dt / 4 and at 4x the solver
// iterations, each robot's path sampled every `cycle` seconds (default 1: the gait's cycle)
// from `settle` seconds on (default 0) compared (check_accuracy, gaitlab/accuracy.h); reports a
// warning per setting that changes a robot's path by more than 3 % and returns what it
// measured. The simulation itself is not touched.
int simulation_check_accuracy(lua_State* L) {
    return protect(L, [&] {
        const std::shared_ptr<Simulation> kept = check_sim(L, 1);
        const Simulation& sim = *kept;
        double seconds = 20, cycle = 1, settle = 0;
        if (!lua_isnoneornil(L, 2)) {
            Fields f(L, 2, 2, {"seconds", "cycle", "settle"});
            seconds = f.number("seconds", seconds);
            if (!(std::isfinite(seconds) && seconds > 0))
                f.fail("seconds", "a positive number of seconds expected");
            // the longest of the runs, at dt / 4, must fit (checked again by check_accuracy)
            try {
                checked_ticks("seconds", seconds, sim.options().dt / 4);
            } catch (const SpecError& e) {
                f.fail("seconds", e.what());
            }
            settle = f.number("settle", settle);
            if (!(std::isfinite(settle) && settle >= 0 && settle < seconds))
                f.fail("settle",
                       fmt::format("seconds in [0, seconds) = [0, {:g}) expected", seconds));
            cycle = f.number("cycle", std::min(cycle, seconds - settle));
            const double dt = sim.options().dt;
            if (!(std::isfinite(cycle) && cycle >= dt && cycle <= seconds - settle)) {
                f.fail("cycle", fmt::format("the gait's cycle in seconds expected, in [dt, seconds "
                                            "- settle] = [{:g}, {:g}]",
                                            dt, seconds - settle));
            }
        }
        lua_State* main = main_thread(L);
        Guard* guard = &Guard::of(L);
        const InterruptScope interruptible(L);  // Ctrl-C in an interpreter (guard.h)
        const AccuracyReport found = check_accuracy(
            sim.world(), sim.options(), seconds, cycle, settle, [main, guard](Simulation& run) {
                run.set_controller_error_handler(
                    [main](const Controller& c, const std::exception& e) {
                        report(main, fmt::format("accuracy check: controller '{}' failed: {}",
                                                 c.name(), e.what()));
                    });
                run.add_pre_tick([guard](Simulation&) {
                    if (guard->interrupted() != 0) throw Error(guard->interrupt_message());
                });
            });
        for (const std::string& w : found.warnings)
            report(main, "warning: " + w);
        const auto push_run = [&](const AccuracyRun& r) {
            lua_createtable(L, 0, 4);
            lua_pushnumber(L, r.path);
            lua_setfield(L, -2, "path");
            lua_pushnumber(L, r.displacement.x);
            lua_setfield(L, -2, "x");
            lua_pushnumber(L, r.displacement.y);
            lua_setfield(L, -2, "y");
            lua_pushnumber(L, rad_to_deg(r.turned));
            lua_setfield(L, -2, "turned");
        };
        const auto push_options = [&](const SimulationOptions& o) {
            lua_createtable(L, 0, 3);
            lua_pushnumber(L, o.dt);
            lua_setfield(L, -2, "dt");
            lua_pushinteger(L, o.control_every);
            lua_setfield(L, -2, "control_every");
            lua_pushinteger(L, o.solver_iterations);
            lua_setfield(L, -2, "solver_iterations");
        };
        const auto set_number = [&](const char* key, double value) {
            lua_pushnumber(L, value);
            lua_setfield(L, -2, key);
        };
        lua_createtable(L, 0, 4);
        set_number("seconds", found.seconds);
        set_number("cycle", found.cycle);
        set_number("settle", found.settle);
        lua_createtable(L, 0, 3);
        push_options(found.given);
        lua_setfield(L, -2, "given");
        if (found.dt_checked) {
            push_options(found.finer_dt);
            lua_setfield(L, -2, "dt");
        }
        push_options(found.more_iterations);
        lua_setfield(L, -2, "iterations");
        lua_setfield(L, -2, "settings");
        lua_createtable(L, static_cast<int>(found.robots.size()), 0);
        for (size_t r = 0; r < found.robots.size(); ++r) {
            const AccuracyRobot& robot = found.robots[r];
            lua_createtable(L, 0, 8);
            lua_pushstring(L, robot.name.c_str());
            lua_setfield(L, -2, "name");
            push_run(robot.given);
            lua_setfield(L, -2, "given");
            if (found.dt_checked) {
                push_run(robot.finer_dt);
                lua_setfield(L, -2, "dt");
                set_number("dt_off", robot.dt_off);
            }
            push_run(robot.more_iterations);
            lua_setfield(L, -2, "iterations");
            set_number("iterations_off", robot.iterations_off);
            lua_rawseti(L, -2, static_cast<lua_Integer>(r + 1));
        }
        lua_setfield(L, -2, "robots");
        lua_createtable(L, static_cast<int>(found.warnings.size()), 0);
        for (size_t i = 0; i < found.warnings.size(); ++i) {
            lua_pushstring(L, found.warnings[i].c_str());
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        lua_setfield(L, -2, "warnings");
        return 1;
    });
}

// sim:robot(name): the handle of this simulation's robot called `name` (its label: "snake",
// "snake_2" ...)
int simulation_robot(lua_State* L) {
    return protect(L, [&] {
        SimulationHandle& h = check_handle(L, 1);
        const std::shared_ptr<Simulation> sim = h.sim;
        const std::string name = check_string(L, 2);
        std::vector<std::string> labels;
        int r = -1;
        for (int i = 0; i < sim->robot_count(); ++i) {
            labels.push_back(sim->robot_label(i));
            if (labels.back() == name) r = i;
        }
        if (r < 0) {
            std::string message = "the simulation has no robot '" + name + "'" +
                                  did_you_mean(name, labels) + " (its robots:";
            for (size_t i = 0; i < labels.size(); ++i)
                message += (i ? ", " : " ") + labels[i];
            throw ArgError(2, message + (labels.empty() ? " none)" : ")"));
        }
        push_robot(L, robot_handle(h, r));
        return 1;
    });
}

int simulation_reset(lua_State* L) {
    return protect(L, [&] {
        check_sim(L, 1)->reset(default_origin(L));
        return 0;
    });
}

// sim:objects(): the world's dynamic objects (boxes, then cylinders, with mass > 0) as
// { object = "box 2", position =, orientation =, velocity = }
int simulation_objects(lua_State* L) {
    return protect(L, [&] {
        const std::shared_ptr<Simulation> kept = check_sim(L, 1);
        Simulation& sim = *kept;
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
            lua_createtable(L, 0, 4);
            lua_pushstring(L, names[k].c_str());
            lua_setfield(L, -2, "object");
            set_body_state(L, sim.object(static_cast<int>(k)));
            lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
        }
        return 1;
    });
}

int simulation_index(lua_State* L) {
    return protect(L, [&] {
        const std::shared_ptr<Simulation> kept = check_sim(L, 1);
        Simulation& sim = *kept;
        // all of the key: 'run\0x' is no method
        const std::string k = lua_type(L, 2) == LUA_TSTRING ? to_string(L, 2) : "";
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
        } else if (k == "solver") {
            lua_pushstring(L, to_string(sim.options().solver));
        } else if (k == "newton_steps") {
            lua_pushinteger(L, sim.options().newton_steps);
        } else if (k == "warnings") {
            const std::vector<std::string>& w = sim.warnings();
            lua_createtable(L, static_cast<int>(w.size()), 0);
            for (size_t i = 0; i < w.size(); ++i) {
                lua_pushstring(L, w[i].c_str());
                lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
            }
        } else if (k == "paused") {
            lua_pushboolean(L, sim.paused());
        } else if (k == "playing") {
            lua_pushboolean(L, check_handle(L, 1).player->playing());
        } else if (k == "speed") {
            lua_pushnumber(L, check_handle(L, 1).player->speed());
        } else if (k == "delay") {
            lua_pushnumber(L, check_handle(L, 1).player->delay());
        } else if (k == "name") {
            const SimulationHandle& h = check_handle(L, 1);
            if (h.name.empty()) {
                lua_pushnil(L);
            } else {
                lua_pushstring(L, h.name.c_str());
            }
        } else if (k == "duration") {
            const SimulationHandle& h = check_handle(L, 1);
            if (h.duration) {
                lua_pushnumber(L, *h.duration);
            } else {
                lua_pushnil(L);
            }
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
            raw_getfield(L, lua_upvalueindex(1), k);
        }
        return 1;
    });
}

int simulation_tostring(lua_State* L) {
    return protect(L, [&] {
        const std::shared_ptr<Simulation> kept = check_sim(L, 1);
        Simulation& sim = *kept;
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
                                {"clone", simulation_clone},
                                {"check_accuracy", simulation_check_accuracy},
                                {"robot", simulation_robot},
                                {"save", simulation_save},
                                {"objects", simulation_objects},
                                {"record", simulation_record},
                                {"flush", simulation_flush},
                                {"live", live_new},
                                {"play", simulation_play},
                                {"pause", simulation_pause},
                                {"status", simulation_status},
                                {"view", simulation_view},
                                {nullptr, nullptr}};
    const luaL_Reg meta[] = {{"__tostring", simulation_tostring},
                             {"__newindex", simulation_newindex},
                             {nullptr, nullptr}};
    register_type_with_fields<SimulationHandle>(L, kSimulationType, methods, simulation_index,
                                                meta);
    Recordings::install(L);
    Playback::install(L);

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
