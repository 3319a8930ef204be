#include "recording.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/files.h"
#include "gaitlab/terminal.h"
#include "guard.h"
#include "hot_reload.h"
#include "lua_util.h"
#include "playback.h"

namespace gaitlab::scripting {

namespace fs = std::filesystem;

namespace {

constexpr const char* kRecordingsKey = "gaitlab.recordings";
constexpr const char* kRecordingsType = "gaitlab.Recordings";

// print(...) as Lua's, to stdout (unless a replay mutes it) and to the logs of the recordings
int l_print(lua_State* L) {
    // the conversions may raise Lua errors: done before any C++ object exists
    const int n = lua_gettop(L);
    for (int i = 1; i <= n; ++i)
        luaL_tolstring(L, i, nullptr);
    return protect(L, [&] {
        std::string line;
        for (int i = 1; i <= n; ++i) {
            size_t len = 0;
            const char* s = lua_tolstring(L, n + i, &len);
            if (i > 1) line += '\t';
            line.append(s, len);
        }
        Recordings& r = Recordings::of(L);
        if (r.print_to_stdout && r.output) {
            r.output(line + "\n");
        } else if (r.print_to_stdout) {
            Playback::of(L).before_output();
            std::fwrite(line.data(), 1, line.size(), stdout);
            std::fputc('\n', stdout);
            std::fflush(stdout);
        }
        r.log_line(line);
        return 0;
    });
}

// os.exit(...) ends the process without closing the Lua state: close the recordings first
// ("finished", or "failed" for a failure status), then exit as Lua's os.exit does
int l_exit(lua_State* L) {
    bool ok = true;
    if (lua_isboolean(L, 1)) {
        ok = lua_toboolean(L, 1);
    } else if (!lua_isnoneornil(L, 1)) {
        ok = luaL_optinteger(L, 1, 0) == 0;
    }
    protect(L, [&] {
        try {
            Recordings::of(L).finish(ok ? "" : "the script called os.exit with a failure status");
        } catch (const std::exception& e) {
            report_line(e.what());
        }
        return 0;
    });
    // what the script printed must have reached stdout: if it did not, the exit status says so
    errno = 0;
    const bool flushed = std::fflush(stdout) == 0;
    const int error = errno;
    if (!flushed || std::ferror(stdout)) {
        if (!flushed && error != EPIPE && error != 0) {
            print_message(stderr, "gaitlab: cannot write to standard output: %s\n",
                          std::strerror(error));
        } else if (flushed) {
            print_message(stderr,
                          "gaitlab: cannot write to standard output: some of the output was "
                          "lost\n");
        }
        if (ok) {
            lua_settop(L, std::max(lua_gettop(L), 1));
            lua_pushinteger(L, !flushed && error == EPIPE ? 128 + SIGPIPE : 1);
            lua_replace(L, 1);
        }
    }
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

// the folders from `dir` up that do not exist yet, deepest first
std::vector<std::string> missing_folders(const std::string& dir) {
    std::vector<std::string> missing;
    std::error_code ec;
    fs::path p = fs::absolute(dir.empty() ? "." : dir, ec).lexically_normal();
    while (!ec && p.has_relative_path() && !fs::exists(p, ec)) {
        missing.push_back(p.string());
        p = p.parent_path();
    }
    return missing;
}

// the options in which the replayed simulation (`here`) differs from the run, each as "NAME
// HERE here, RUN in the run"; empty when they are the same
std::vector<std::string> option_differences(const SimulationOptions& here,
                                            const SimulationOptions& run) {
    std::vector<std::string> out;
    const auto differ = [&](const char* name, const auto& a, const auto& b) {
        out.push_back(fmt::format("{} {} here, {} in the run", name, a, b));
    };
    if (here.dt != run.dt) differ("dt", here.dt, run.dt);
    if (here.control_every != run.control_every)
        differ("control_every", here.control_every, run.control_every);
    if (here.solver_iterations != run.solver_iterations)
        differ("solver_iterations", here.solver_iterations, run.solver_iterations);
    if (here.solver != run.solver) differ("solver", to_string(here.solver), to_string(run.solver));
    if (here.newton_steps != run.newton_steps) {
        // the one a script need not have changed: chosen for the world when not given, as
        // runs before 2026-11-30 did not, and 4 until kLongChainNewtonSteps became 8
        differ("newton_steps", here.newton_steps, run.newton_steps);
        if (here.newton_steps == kLongChainNewtonSteps &&
            (run.newton_steps == 0 || run.newton_steps == 4)) {
            out.back() += fmt::format(
                " (a pitch-yaw chain of {} modules or more gets {} when newton_steps is not "
                "given, since 2026-11-30; runs recorded before got 0, then 4: give newton_steps "
                "= {} to replay this run)",
                kLongChainJoints + 1, kLongChainNewtonSteps, run.newton_steps);
        }
    }
    if (here.seed != run.seed) differ("seed", here.seed, run.seed);
    if (here.on_controller_error != run.on_controller_error) {
        differ("on_controller_error", to_string(here.on_controller_error),
               to_string(run.on_controller_error));
    }
    return out;
}

}  // namespace

std::string signal_name(int signal) {
    if (signal == kReplayEndSignal) return "the end of the replayed run";
    switch (signal) {
        case SIGINT:
            return "SIGINT";
        case SIGTERM:
            return "SIGTERM";
        case SIGHUP:
            return "SIGHUP";
        case SIGPIPE:
            return "SIGPIPE";
        case SIGQUIT:
            return "SIGQUIT";
        default:
            return fmt::format("signal {}", signal);
    }
}

void log_to_recordings(lua_State* L, const std::string& line) {
    if (lua_getfield(L, LUA_REGISTRYINDEX, kRecordingsKey) == LUA_TUSERDATA) {
        static_cast<Recordings*>(lua_touserdata(L, -1))->log_line(line);
    }
    lua_pop(L, 1);
}

Recordings& Recordings::of(lua_State* L) {
    lua_getfield(L, LUA_REGISTRYINDEX, kRecordingsKey);
    auto* r = static_cast<Recordings*>(lua_touserdata(L, -1));
    lua_pop(L, 1);
    return *r;
}

void Recordings::install(lua_State* L) {
    register_type<Recordings>(L, kRecordingsType, nullptr);
    Guard& guard = Guard::of(L);
    Recordings* r = new_object<Recordings>(L, kRecordingsType, Recordings{});
    r->guard_ = &guard;
    lua_setfield(L, LUA_REGISTRYINDEX, kRecordingsKey);
    if (guard.owner() == StateOwner::interpreter) {
        // an interpreter's print and os.exit stay its own (docs/embedding.md); its run folders
        // are named after the script it runs (lua.c's arg[0])
        const int top = lua_gettop(L);
        if (raw_getglobal(L, "arg") == LUA_TTABLE && lua_rawgeti(L, -1, 0) == LUA_TSTRING) {
            const fs::path script = to_string(L, -1);
            if (script.extension() == ".lua" && !script.stem().empty()) {
                r->settings.name = script.stem().string();
            }
        }
        lua_settop(L, top);
    } else {
        lua_pushcfunction(L, l_print);
        raw_setglobal(L, "print");
        if (raw_getglobal(L, "os") == LUA_TTABLE) {
            raw_getfield(L, -1, "exit");
            lua_pushcclosure(L, l_exit, 1);
            raw_setfield(L, -2, "exit");
        }
        lua_pop(L, 1);
    }
    // every controller file that loads or reloads goes into the run folders, and a reload is
    // an event of every simulation (a replay applies it again at the same tick)
    Reloader::of(L).set_observer([](lua_State* S, const Reloader::Change& c) {
        Recordings::of(S).on_file(c.index, c.chunk, c.source, c.version, c.origin);
    });
}

std::string Recordings::config_path(size_t index, const std::string& chunk) const {
    // a replay names the files as the run did (a script may load a file whose name changes
    // from run to run, e.g. os.tmpname())
    if (replay && index < replay->controller_paths.size()) return replay->controller_paths[index];
    std::error_code ec;
    const fs::path file = fs::weakly_canonical(chunk, ec);
    if (!settings.script.empty()) {
        const fs::path dir = fs::weakly_canonical(settings.script, ec).parent_path();
        const fs::path rel = file.lexically_relative(dir);
        const bool inside = !rel.empty() && *rel.begin() != ".." && !rel.is_absolute();
        if (inside && rel != fs::path(settings.script).filename()) return rel.string();
    }
    // outside the script's folder: config/external/N-NAME
    return fmt::format("external/{}-{}", index + 1, file.filename().string());
}

std::string Recordings::reload_path(size_t index, const std::string& path, std::uint64_t version) {
    return fmt::format("reloads/{}-{}.v{}.lua", index + 1, fs::path(path).stem().string(), version);
}

RunContext Recordings::context(lua_State* L, int index, const std::string& started_by) const {
    RunContext c;
    c.args = script_args;
    c.script_seed = script_seed;
    c.simulation = index;
    c.started_by = started_by;
    if (!settings.script.empty()) {
        c.script = fs::path(settings.script).filename().string();
        c.files.push_back({"script", c.script, settings.script, script_source, "", 0, ""});
    }
    for (const ConfigFile& f : settings.files)
        c.files.push_back(f);
    for (const ConfigFile& f : inputs_)
        c.files.push_back(f);
    const std::vector<Reloader::FileRecord> files = Reloader::of(L).history();
    for (size_t k = 0; k < files.size(); ++k) {
        const std::string path = config_path(k, files[k].chunk);
        c.files.push_back({"controller", path, files[k].chunk, files[k].versions[0], "", 0, ""});
        for (size_t v = 1; v < files[k].versions.size(); ++v) {
            c.files.push_back({"reload", reload_path(k, path, v), files[k].chunk,
                               files[k].versions[v], path, v, ""});
        }
    }
    c.provenance.emplace_back("lua", LUA_RELEASE);
    if (!settings.command.empty()) c.provenance.emplace_back("command", settings.command);
    return c;
}

std::string Recordings::next_dir() {
    if (settings.dir.empty()) return default_run_dir(settings.root, settings.name);
    // DIR, DIR-2, DIR-3 ...: the next one no simulation of this state has taken
    for (;;) {
        ++dirs_;
        const std::string dir =
            dirs_ == 1 ? settings.dir : fmt::format("{}-{}", settings.dir, dirs_);
        const std::string abs = fs::absolute(dir).lexically_normal().string();
        const bool taken = std::any_of(claimed_.begin(), claimed_.end(),
                                       [&](const auto& c) { return c.first == abs; });
        if (!taken) return dir;
    }
}

std::string Recordings::claim(const std::string& dir, int index) const {
    // the same folder under another name is the same folder: links and ".." resolved
    std::error_code ec;
    fs::path abs = fs::weakly_canonical(fs::absolute(dir), ec);
    if (ec) abs = fs::absolute(dir).lexically_normal();
    std::string path = abs.string();
    while (path.size() > 1 && path.back() == '/')
        path.pop_back();
    for (const auto& [other, k] : claimed_) {
        if (other != path) continue;
        throw IoError(fmt::format(
            "cannot record into {}: simulation {} of this script recorded into it{} (give "
            "each simulation its own folder)",
            dir, k, k == index ? " already" : ""));
    }
    return path;
}

std::string Recordings::begin(lua_State* L, SimulationHandle& h, const RecordRequest& request,
                              const std::string& started_by) {
    RecordOptions o = request.options;
    // default_run_dir makes a new folder (and the root, if missing); any other folder the
    // recorder makes if it is missing
    const bool made_here = request.dir.empty() && settings.dir.empty();
    const std::vector<std::string> roots_made =
        made_here ? missing_folders(settings.root) : std::vector<std::string>{};
    o.dir = request.dir.empty() ? next_dir() : request.dir;
    std::string claimed;
    std::shared_ptr<Recorder> rec;
    try {
        // two simulations of one script never share a folder (the second would empty the
        // first's)
        claimed = claim(o.dir, h.index);
        rec = std::make_shared<Recorder>(*h.sim, o, context(L, h.index, started_by));
    } catch (const std::exception&) {
        // a recording refused before it wrote anything (a pattern that matches nothing ...)
        // leaves no empty folder of ours behind; rmdir removes nothing else, and a recorder
        // that got as far as run.json leaves it saying why it failed
        if (made_here && ::rmdir(o.dir.c_str()) == 0) {
            for (const std::string& f : roots_made) {
                if (::rmdir(f.c_str()) != 0) break;
            }
        }
        throw;
    }
    claimed_.emplace_back(std::move(claimed), h.index);
    h.recorder = rec;
    recorders_.push_back(rec);
    folders_.push_back(o.dir);
    return o.dir;
}

void Recordings::begin_replay(lua_State* L, SimulationHandle& h, const std::string& started_by) {
    ReplayPlan& p = *replay;
    if (started_by != p.started_by) {
        p.mismatch = fmt::format(
            "the run started recording {} and the replay {}",
            p.started_by == "simulation" ? "when the simulation was created" : "with sim:record",
            started_by == "simulation" ? "when the simulation was created" : "with sim:record");
    }
    const std::vector<std::string> differ = option_differences(h.sim->options(), p.expect);
    if (!differ.empty()) {
        p.mismatch = fmt::format("the replayed simulation has other options than the run: {}",
                                 fmt::join(differ, "; "));
    }
    RecordOptions o = p.options;
    o.dir = p.into;
    h.recorder = std::make_shared<Recorder>(*h.sim, o, context(L, h.index, started_by));
    recorders_.push_back(h.recorder);
    folders_.push_back(o.dir);
    p.sim = h.sim;
    p.recorder = h.recorder;
    // recorded reloads of controller code from disk run the recorded version again
    auto apply = [L = main_thread(L)](Simulation&, const Event& e) {
        ReplayPlan& plan = *Recordings::of(L).replay;
        for (size_t k = 0; k < plan.controller_paths.size(); ++k) {
            if (plan.controller_paths[k] != e.name) continue;
            const std::string error = Reloader::of(L).reload_file(L, k, e.origin);
            if (!error.empty()) throw Error(error);
            return;
        }
        throw Error(fmt::format("the run has no controller file '{}'", e.name));
    };
    p.replay = std::make_unique<EventReplay>(*h.sim, p.events, apply, p.stop_tick);
    // where the run stopped, the script stops too, even if it catches errors (a run stopped by
    // a signal inside `while true do pcall(...) end` would replay forever): the same interrupt
    // a signal gives, which replay() clears once the script has stopped
    p.replay->on_end([L = main_thread(L)] { Guard::of(L).interrupt(L, kReplayEndSignal); });
}

void Recordings::created(lua_State* L, SimulationHandle& h, const RecordRequest& request) {
    h.index = ++created_;
    // scripts may make thousands of simulations: forget the ones that are gone
    sims_.erase(
        std::remove_if(sims_.begin(), sims_.end(), [](const auto& w) { return w.expired(); }),
        sims_.end());
    recorders_.erase(std::remove_if(recorders_.begin(), recorders_.end(),
                                    [](const auto& w) { return w.expired(); }),
                     recorders_.end());
    sims_.push_back(h.sim);
    if (replay) {
        if (h.index == replay->simulation && replay->started_by == "simulation") {
            begin_replay(L, h, "simulation");
        }
    } else if (!settings.disabled) {
        const bool on = request.mode == RecordRequest::Mode::on ||
                        (request.mode == RecordRequest::Mode::absent && settings.by_default);
        if (on) begin(L, h, request, "simulation");
    }
    for (const auto& fn : on_created)
        fn(*h.sim, h.index);
}

std::string Recordings::start(lua_State* L, SimulationHandle& h, const RecordRequest& request) {
    if (h.recorder && !h.recorder->closed()) {
        throw Error(
            fmt::format("the simulation already records into {} (sim:record(false) stops that)",
                        h.recorder->dir()));
    }
    if (replay) {
        if (h.index != replay->simulation || replay->sim) return "";
        begin_replay(L, h, "record");
        return replay->into;
    }
    if (settings.disabled) return "";
    return begin(L, h, request, "record");
}

void Recordings::stop(SimulationHandle& h) {
    if (h.recorder) h.recorder->close();
    // a replay follows the run only while it recorded
    if (replay && replay->sim == h.sim && replay->replay) replay->replay->detach();
}

void Recordings::finish(const std::string& error) {
    std::string first;
    const int signal = guard_ ? guard_->interrupted() : 0;
    for (const auto& w : recorders_) {
        auto rec = w.lock();
        if (!rec || rec->closed()) continue;
        try {
            if (signal != 0) {
                rec->close("interrupted", signal_name(signal));
            } else {
                rec->close(error.empty() ? "finished" : "failed", error);
            }
        } catch (const std::exception& e) {
            if (first.empty()) first = e.what();
        }
    }
    recorders_.clear();
    if (!first.empty()) throw IoError(first);
}

void Recordings::log_line(const std::string& line) {
    for (const auto& w : recorders_) {
        if (auto rec = w.lock()) rec->log(line);
    }
}

void Recordings::on_input(const std::string& path) {
    std::error_code ec;
    const std::string origin = fs::weakly_canonical(path, ec).string();
    for (const ConfigFile& f : inputs_) {
        if (f.origin == origin) return;
    }
    ConfigFile f;
    try {
        // bounded, and never waiting on a FIFO: the same reader the bindings use
        f.content = read_file(origin);
    } catch (const Error&) {
        return;  // the reader of the file reports it
    }
    f.role = "input";
    f.origin = origin;
    // inside the script's folder a copy at the same place is found by the same relative path;
    // outside, under external/ + its absolute path, so files that name each other by relative
    // paths (a simulation file and its parts) still find each other
    f.path = "external" + origin;
    if (!settings.script.empty()) {
        const fs::path dir = fs::weakly_canonical(settings.script, ec).parent_path();
        const fs::path rel = fs::path(origin).lexically_relative(dir);
        if (!rel.empty() && *rel.begin() != ".." && !rel.is_absolute()) f.path = rel.string();
    }
    for (const auto& w : recorders_) {
        auto rec = w.lock();
        if (rec && !rec->closed()) rec->add_config_file(f);
    }
    inputs_.push_back(std::move(f));
}

std::string input_path(lua_State* L, const std::string& arg) {
    const std::string path = script_path(L, arg);
    Recordings& r = Recordings::of(L);
    const std::string read = r.input_path(path);
    r.on_input(read);
    return read;
}

std::string Recordings::input_path(const std::string& path) const {
    if (!replay || replay->inputs.empty()) return path;
    std::error_code ec;
    const auto it = replay->inputs.find(fs::weakly_canonical(path, ec).string());
    return it != replay->inputs.end() ? it->second : path;
}

void Recordings::on_file(size_t index, const std::string& chunk, const std::string& source,
                         std::uint64_t version, Origin origin) {
    const std::string path = config_path(index, chunk);
    ConfigFile f;
    f.origin = chunk;
    f.content = source;
    if (version == 0) {
        f.role = "controller";
        f.path = path;
    } else {
        f.role = "reload";
        f.path = reload_path(index, path, version);
        f.of = path;
        f.version = version;
    }
    for (const auto& w : recorders_) {
        auto rec = w.lock();
        if (rec && !rec->closed()) rec->add_config_file(f);
    }
    if (version == 0) return;
    Event e;
    e.kind = EventKind::reload;
    e.origin = origin;
    e.name = path;
    e.value = static_cast<double>(version);
    e.detail = "config/" + f.path;
    for (const auto& w : sims_) {
        if (auto sim = w.lock()) sim->post_event(e);
    }
}

}  // namespace gaitlab::scripting
