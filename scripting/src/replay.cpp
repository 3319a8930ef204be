#include "gaitlab/scripting/replay.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>

#include <fmt/format.h>

#include "gaitlab/files.h"
#include "gaitlab/replay.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/simulation.h"
#include "hot_reload.h"
#include "recording.h"

namespace gaitlab::scripting {

namespace fs = std::filesystem;

namespace {

// a file of the run's config/, as run.json or events.csv names it: never outside config/,
// never a FIFO or device, bounded (gaitlab::read_file)
std::string read_config(const RunData& run, const std::string& path) {
    const std::string file = run.config_file(path);
    std::error_code ec;
    if (!fs::exists(file, ec)) throw Error(fmt::format("cannot replay: {} is missing", file));
    return read_file(file);
}

// whether the run was recorded by a console session (`gaitlab console`, `gaitlab -i`) or with
// the viewer (`gaitlab run FILE --view`): after its script, the typed commands (sim:play(),
// sim:run ...) or the page's play and step buttons stepped the simulation on
bool from_console(const RunMeta& m) {
    for (const auto& [key, value] : m.provenance) {
        if (key != "command") continue;
        if (value.rfind("gaitlab console", 0) == 0) return true;
        if (value.rfind("gaitlab run ", 0) != 0) return false;
        // gaitlab's own options stand before "--"; after it, everything is the script's
        size_t at = 0;
        while (at < value.size()) {
            const size_t end = std::min(value.find(' ', at), value.size());
            const std::string word = value.substr(at, end - at);
            if (word == "--") return false;
            if (word == "--view") return true;
            at = end + 1;
        }
        return false;
    }
    return false;
}

// steps `sim` on as a console's commands did: to the tick of each recorded change that came from
// elsewhere (a reset there starts the ticks again), then to tick `last`; a controller failure
// on the way (the console paused, then a reload or a reset let it go on) steps on too. Returns
// the error that stopped it ("" if it got there)
std::string step_on(Simulation& sim, EventReplay& replay, const std::vector<Event>& events,
                    long last) {
    for (;;) {
        replay.apply_due();
        const size_t k = replay.matched();
        long target = last;
        if (k < events.size() && events[k].origin != Origin::script &&
            events[k].tick > sim.ticks()) {
            target = events[k].tick;
        }
        if (target <= sim.ticks() || !replay.divergence().empty()) return "";
        const long before = sim.ticks();
        try {
            sim.step(target - before);
        } catch (const ReplayEnd&) {
            throw;
        } catch (const std::exception& e) {
            if (sim.ticks() == before) return e.what();
        }
    }
}

// an error message with the folders of the files it names left out ("cf/config/a/b.lua:7: x"
// and ".../a/b.lua:7: x" are "b.lua:7: x"): the run and its replay ran the same files from
// different folders (the replay's are in RUN/config/), and Lua shortens long names with "..."
std::string located_in_file(const std::string& message) {
    static const std::regex folders(R"([^\s'"(]*/([^/\s'"(]+:[0-9]+:))");
    return std::regex_replace(message, folders, "$1");
}

}  // namespace

ReplayResult replay(const std::string& run_dir, const std::string& into,
                    const std::function<void(LuaHost*)>& on_host) {
    const RunData run(run_dir);
    const RunMeta& m = run.meta();
    if (m.script.empty()) {
        throw Error(
            fmt::format("cannot replay {}: it holds no script (only runs recorded from a "
                        "script can be replayed)",
                        run_dir));
    }
    const fs::path dir(run_dir);
    ReplayResult result;
    std::string base = run_dir;
    while (base.size() > 1 && base.back() == '/')
        base.pop_back();
    result.into = into.empty() ? base + "-replay" : into;
    if (fs::weakly_canonical(result.into) == fs::weakly_canonical(dir)) {
        throw Error("cannot replay a run into its own folder");
    }
    // a run still being written has no end yet to compare with: its replay would "differ"
    if (m.status == "running" && liveness(m.process) == Liveness::alive) {
        throw Error(
            fmt::format("cannot replay {}: it is still being recorded (by process {}); "
                        "replay it once that run has ended",
                        run_dir, m.process.pid));
    }

    // a run that its script or a controller stopped with an error: the replay must stop with
    // the same error at the same tick (a failed write, a full disk, stopped only the recording)
    const bool run_failed = m.status == "failed" && !m.recording_failed;
    std::string replay_error;

    auto plan = std::make_shared<ReplayPlan>();
    plan->into = result.into;
    plan->simulation = m.simulation;
    plan->started_by = m.started_by;
    plan->options.record_every = m.record_every;
    plan->options.flush_seconds = m.flush_seconds;
    plan->options.series = m.select;
    plan->expect = m.options;
    plan->events = run.events();
    if (m.status == "interrupted" && m.last_tick >= 0) {
        // a signal stopped the run: replay up to the tick where it stopped
        plan->stop_tick = m.last_tick;
    } else if (m.status == "running" || (m.status == "failed" && m.recording_failed)) {
        // the process ended without closing the run, or a write failed (a full disk) and the
        // recording stopped there: replay up to its last complete row
        const std::vector<double> t = run.times();
        const double ticks = t.empty() ? 0 : std::round(t.back() / m.options.dt);
        plan->stop_tick = ticks >= 0 && ticks < 9e18 ? static_cast<long>(ticks) : 0;
    }
    for (const ConfigFile& f : m.files) {
        if (f.role == "controller") {
            plan->controller_paths.push_back(f.path);
            plan->controller_sources.push_back(read_config(run, f.path));
        }
    }
    // every saved version of a controller file: those listed in run.json, and those the
    // events name (a run that was killed did not list them)
    auto add_version = [&](const std::string& of, std::uint64_t version, const std::string& path) {
        for (size_t k = 0; k < plan->controller_paths.size(); ++k) {
            if (plan->controller_paths[k] == of) {
                plan->reload_sources[{k, version}] = read_config(run, path);
            }
        }
    };
    for (const ConfigFile& f : m.files) {
        if (f.role == "reload") add_version(f.of, f.version, f.path);
    }
    // files the run read: a replay reads the run folder's copies
    for (const ConfigFile& f : m.files) {
        if (f.role == "input") plan->inputs[f.origin] = run.config_file(f.path);
    }
    for (const Event& e : plan->events) {
        if (e.kind == EventKind::reload && e.detail.rfind("config/", 0) == 0) {
            add_version(e.name, static_cast<std::uint64_t>(e.value), e.detail.substr(7));
        }
    }

    const std::string script = run.config_file(m.script);
    read_config(run, m.script);  // a regular file of config/ (a FIFO there would block the load)
    {
        LuaHost host;
        lua_State* L = host.state();
        host.set_print(false);
        host.set_reporter([L](const std::string&) {});  // reports go to the replay's log
        RecordSettings settings;
        settings.script = script;
        settings.command = "gaitlab replay " + run_dir;
        host.set_recording(settings);
        host.seed(m.script_seed);
        host.set_args(script, m.args);
        Recordings& rec = Recordings::of(L);
        rec.replay = plan;
        // controller files come from the run folder, in the order the run loaded them
        Reloader& reloader = Reloader::of(L);
        reloader.set_polling(false);
        reloader.set_source_override(
            [plan](size_t index, std::uint64_t version) -> std::optional<std::string> {
                if (version == 0) {
                    if (index < plan->controller_sources.size()) {
                        return plan->controller_sources[index];
                    }
                    return std::nullopt;
                }
                const auto it = plan->reload_sources.find({index, version});
                if (it != plan->reload_sources.end()) return it->second;
                return std::nullopt;
            });
        // the caller may interrupt the script from here until the host goes
        struct Announce {
            const std::function<void(LuaHost*)>& fn;
            Announce(const std::function<void(LuaHost*)>& f, LuaHost* h) : fn(f) {
                if (fn) fn(h);
            }
            ~Announce() {
                if (fn) fn(nullptr);
            }
        } announce(on_host, &host);
        std::string error;
        try {
            if (script.size() > 4 && script.compare(script.size() - 4, 4, ".xml") == 0) {
                host.run_simulation_file(script);
            } else {
                host.run_file(script);
            }
        } catch (const std::exception& e) {
            error = e.what();
        }
        // what the console's commands did after the script: the run records the changes
        // typed there as events, not how far each command stepped; the simulation goes on to
        // the tick the run ended at, the changes applying at their ticks
        if (error.empty() && plan->replay && !plan->replay->ended() && plan->sim &&
            plan->recorder && !plan->recorder->closed() && from_console(m)) {
            const long last = plan->stop_tick >= 0 ? plan->stop_tick : m.last_tick;
            try {
                error = step_on(*plan->sim, *plan->replay, plan->events, last);
            } catch (const ReplayEnd&) {
                // the run stopped there (interrupted): so does the replay
            } catch (const std::exception& e) {
                error = e.what();
            }
        }
        if (plan->replay) {
            if (plan->replay->ended()) {
                result.stopped_early = true;
                error.clear();
            } else if (error.empty()) {
                plan->replay->apply_due();  // changes made after the last step
            }
            result.divergence = plan->replay->divergence();
            result.applied = plan->replay->applied();
            if (result.divergence.empty() && !result.stopped_early &&
                plan->replay->matched() < plan->events.size()) {
                result.divergence =
                    fmt::format("the replay made {} of the {} changes the run recorded",
                                plan->replay->matched(), plan->events.size());
            }
        } else if (!plan->sim) {
            result.divergence =
                fmt::format("the script did not create simulation {} again", m.simulation);
        }
        if (!plan->mismatch.empty() && result.divergence.empty()) {
            result.divergence = plan->mismatch;
        }
        // the run's own error, if it ended with one, is expected again (checked below, with
        // the tick); an error before the replay recorded (its folder refused ...), or one that
        // stopped the replay from outside, is the replay's own failure
        const int stopped_by = host.interrupted();
        if (run_failed && plan->recorder && (stopped_by == 0 || stopped_by == kReplayEndSignal)) {
            replay_error = error;
        } else if (!error.empty()) {
            result.script_error = error;
        }
        // the end of the run stopped the script (recording.cpp): no interrupt of the caller's
        if (host.interrupted() == kReplayEndSignal) host.clear_interrupt();
        host.finish(error);
        plan->replay.reset();
        plan->recorder.reset();
        plan->sim.reset();
        rec.replay.reset();
    }
    if (!fs::exists(fs::path(result.into) / "run.json")) {
        result.comparison.difference = "the replay recorded nothing";
        return result;
    }
    const RunData replayed(result.into);
    result.comparison = compare(run, replayed);
    if (run_failed) {
        const auto at = [&](long tick) { return static_cast<double>(tick) * m.options.dt; };
        if (replay_error.empty()) {
            result.failure = fmt::format("the run failed at t = {} s ({}) and the replay did not",
                                         at(m.last_tick), m.message);
        } else if (located_in_file(replay_error) != located_in_file(m.message)) {
            result.failure = fmt::format(
                "the run failed at t = {} s with: {}; the replay at t = {} s with: {}",
                at(m.last_tick), m.message, at(replayed.meta().last_tick), replay_error);
        } else if (replayed.meta().last_tick != m.last_tick) {
            result.failure =
                fmt::format("the run failed at t = {} s and the replay at t = {} s: {}",
                            at(m.last_tick), at(replayed.meta().last_tick), m.message);
        } else {
            result.run_error = m.message;
            result.failed_at = at(m.last_tick);
        }
    }
    return result;
}

}  // namespace gaitlab::scripting
