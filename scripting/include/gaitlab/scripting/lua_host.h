// The Lua host: a Lua 5.4 state with the gaitlab API, and the one protected-call helper every
// call into Lua goes through.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gaitlab/error.h"
#include "gaitlab/event.h"
#include "gaitlab/recorder.h"

struct lua_State;

namespace gaitlab {
class Player;
class Simulation;
}  // namespace gaitlab

namespace gaitlab::scripting {

class Guard;

/// How the simulations that scripts create are recorded (docs/data.md). `gaitlab run` records
/// by default; a host made for embedding or tests records only what a script asks for.
struct RecordSettings {
    /// simulations created without `record = ...` record (`gaitlab run`)
    bool by_default = false;
    /// nothing records, whatever the script says (`gaitlab run --no-record`)
    bool disabled = false;
    /// the folder of the first run that has no folder of its own (`--record DIR`); the next
    /// ones get DIR-2, DIR-3, ... "" : ROOT/NAME-YYYYmmdd-HHMMSS
    std::string dir;
    std::string root = "runs";  ///< parent of the default run folders
    std::string name = "run";   ///< run name, usually the script's file name without .lua
    /// the script the host runs (LuaHost::run_file of this path is copied into run folders)
    std::string script;
    std::string command;  ///< the command line, kept as provenance
    /// more configuration to copy into every run folder (the XML master and its parts, with
    /// roles "master", "robot", "actuation", "environment"); paths relative to config/
    std::vector<ConfigFile> files;
};

/// Where a long sim:run(T) or sim:step(n) stands (see LuaHost::set_progress).
struct RunProgress {
    double time = 0;    ///< simulated time now, s
    double start = 0;   ///< simulated time when the run began, s
    double end = 0;     ///< simulated time the run ends at, s
    double wall = 0;    ///< wall seconds since the run began
    bool done = false;  ///< the run ended, or the script writes output: take the line away
};

/// A Lua error, split into its parts (never parsed from strings after the fact).
class ScriptError : public Error {
  public:
    ScriptError(std::string message, std::string file, int line, std::string traceback)
        : Error(message), file_(std::move(file)), line_(line), traceback_(std::move(traceback)) {}
    /// The file the error happened in ("" when unknown, e.g. in C code).
    const std::string& file() const { return file_; }
    /// Its line (0 when unknown).
    int line() const { return line_; }
    /// Lua's stack traceback at the point of the error.
    const std::string& traceback() const { return traceback_; }

  private:
    std::string file_;
    int line_;
    std::string traceback_;
};

/// A bad field of a table a script gave, found by a handler the host calls for it (the
/// OptimizeHandler): the script sees "bad argument #1 to 'optimize' (field 'KEY': MESSAGE)".
class FieldError : public SpecError {
  public:
    FieldError(std::string key, const std::string& message)
        : SpecError(message), key_(std::move(key)) {}
    const std::string& key() const { return key_; }

  private:
    std::string key_;
};

/// Calls the function below `nargs` arguments on top of L's stack in protected mode, with a
/// message handler that records file, line and traceback. On failure the stack is as if the
/// call returned nothing and ScriptError is thrown.
void protected_call(lua_State* L, int nargs, int nresults);

class LuaHost {
  public:
    /// The memory a host's Lua state may hold by default: 2 GiB.
    static constexpr std::size_t kDefaultMemoryLimit = std::size_t{2} << 30;

    /// A new Lua state with the standard libraries and the `gaitlab` module as a global, that
    /// may hold at most `memory_limit` bytes (past it, allocations fail with "not enough
    /// memory", a Lua error like any other).
    explicit LuaHost(std::size_t memory_limit = kDefaultMemoryLimit);
    ~LuaHost();
    LuaHost(const LuaHost&) = delete;
    LuaHost& operator=(const LuaHost&) = delete;

    lua_State* state() const { return L_; }

    /// Seeds math.random, so scripts that use it are reproducible (a new host has seed 0).
    void seed(std::uint64_t seed);
    /// Sets the global `arg` table as lua.c does: arg[0] = script, arg[1..] = args.
    void set_args(const std::string& script, const std::vector<std::string>& args);
    /// Where the host's messages go: failed reloads of controller files ("reload failed:
    /// FILE:LINE: message") and controllers failing under on_controller_error = "continue".
    /// One message per call, without "gaitlab: " or a trailing newline. Without a reporter they
    /// go to stderr as "gaitlab: MESSAGE".
    void set_reporter(std::function<void(const std::string&)> fn);
    /// Wall time between two checks of the controller files for changes (default 0.2 s); a
    /// shorter one takes effect at once.
    void set_reload_interval(double seconds);

    /// How simulations created from now on are recorded (see RecordSettings).
    void set_recording(RecordSettings settings);
    /// The run folders recorded so far, in the order they were started.
    std::vector<std::string> run_folders() const;
    /// Closes every recording still open: "finished", or "failed" with `error` as the reason.
    /// Throws IoError if a last write fails.
    void finish(const std::string& error = {});
    /// Calls `fn` for every simulation a script creates, with its 1-based creation index,
    /// before the script goes on (a console or viewer attaches here).
    void on_simulation(std::function<void(Simulation&, int)> fn);
    /// Calls `fn` for every simulation a script creates, after the on_simulation functions,
    /// with the player that plays it (it holds the simulation: keep it to keep the simulation)
    /// and its creation index: a front end that drives simulations from outside the script (a
    /// viewer) attaches here.
    void on_player(std::function<void(const std::shared_ptr<Player>&, int)> fn);
    /// How sim:run(T) and sim:step(n) advance a simulation: fn(player, index, ticks) must run
    /// `ticks` ticks of player.simulation() (fewer only where Simulation::step would stop
    /// early, or by throwing what it throws) and return how many it ran. Without one (the
    /// default, or an empty function) they step at once, as fast as possible; a viewer paces
    /// them against the wall clock with the player and waits while its page holds them.
    using Runner = std::function<long(Player& player, int index, long ticks)>;
    void set_runner(Runner fn);
    /// Where sim:view{port =, host =} asks the viewer to listen (0 and "": as the viewer
    /// chooses; the first call makes it there).
    struct ViewRequest {
        int port = 0;
        std::string host;
    };
    /// What sim:view() does: fn(player, index, request) shows the simulation in a viewer and
    /// returns its address (a console makes the viewer on the first call). Without one,
    /// sim:view() raises an error saying where it works.
    using ViewHandler = std::function<std::string(const std::shared_ptr<Player>&, int index,
                                                  const ViewRequest& request)>;
    void set_view_handler(ViewHandler fn);
    /// What gaitlab.optimize{...} asks for (docs/lua-api.md, "Optimization"): the spec file and
    /// the options of `gaitlab optimize` as given, each as text ("" : not given; numbers as
    /// decimal text), for the handler to check as the command line's are checked.
    struct OptimizeRequest {
        std::string spec;  ///< the spec file, relative to the calling script's folder resolved
        std::string method, generations, population, workers, seed;
        std::string out;  ///< as given ("" : the handler chooses a new folder)
        bool resume = false;
        /// non-zero (the signal's number) once the host is interrupted (LuaHost::interrupt):
        /// the optimization stops
        const std::atomic<int>* stop = nullptr;
    };
    /// What gaitlab.optimize{...} returns to the script.
    struct OptimizeResult {
        struct Parameter {
            std::string name;
            double value = 0;
            bool integer = false;  ///< given to Lua as an integer
        };
        std::vector<Parameter> parameters;  ///< the best, in the spec's order (by name)
        double fitness = 0;                 ///< the best fitness
        std::int64_t evaluations = 0;
        std::string method;
        int generations = 0;
        int population = 0;
        // absolute paths: a script reads relative ones from its own folder
        std::string folder;      ///< the results folder
        std::string simulation;  ///< the best as a simulation file ("" : it could not be saved)
        std::string run;         ///< its run recorded ("" : none)
        std::string plot;        ///< the convergence plot ("" : none)
    };
    /// What gaitlab.optimize{...} does: runs the optimization (it sits above scripting: the
    /// command line installs it) and returns its result; throws FieldError for a bad option,
    /// Error for the rest. Without one, gaitlab.optimize raises an error saying where it works.
    using OptimizeHandler = std::function<OptimizeResult(const OptimizeRequest&)>;
    void set_optimize_handler(OptimizeHandler fn);
    /// What an interrupt stops the host's code with ("interrupted (SIGINT)"); "" if none.
    std::string interrupt_message() const;
    /// Who makes the changes that code run from now on makes without naming an origin
    /// (`ctl.phase = 90`, `sim:reset()`, `group:drive(ctl)`, `sensor.enabled = false`): their
    /// events are stamped with it (docs/data.md). The console sets Origin::console while it
    /// runs a typed line; the default is Origin::script.
    void set_origin(Origin origin);
    /// The origin set by set_origin.
    Origin origin() const;
    /// Where print() writes instead of stdout (one call per print, the text ends with a
    /// newline); an empty function: stdout again. A console uses it to keep the line being
    /// typed intact.
    void set_output(std::function<void(const std::string&)> fn);
    /// Where the script's print() goes besides the logs of its recordings: stdout (the
    /// default) or nowhere (`false`, for replays).
    void set_print(bool to_stdout);

    /// Asks the code the host runs to stop, as Ctrl-C does in lua.c: the Lua code at its next
    /// instruction (no pcall can catch it) and the simulations at their next tick, so the call
    /// running (run_file, run_simulation_file ...) throws ScriptError("interrupted (SIGINT)").
    /// Async-signal-safe, and safe from another thread. Until clear_interrupt(), every call
    /// into the host's Lua code stops the same way.
    void interrupt(int signal);
    /// The signal given to interrupt(), 0 if none.
    int interrupted() const;
    /// Forgets an interrupt, so the host runs code again (a console back at its prompt).
    void clear_interrupt();

    /// Steps every simulation that plays (sim:play()) as far as its pace allows now: wall time
    /// × sim.speed, one sim.delay per tick, doing at most set_pump_slice() of work in all (a
    /// tick at least per simulation that has one due), so a console stays responsive when it
    /// calls this between keystrokes. Also checks the controller files for changes (hot
    /// reload). Returns the wall seconds until it should be called again: 0 when behind,
    /// +infinity when nothing plays. Never throws: a simulation that fails is paused and
    /// reported through the reporter (it plays again after sim:reset(), or after a fix to the
    /// failed controller's file reloads); an interrupt pauses every playing simulation (clear
    /// it before playing again). Call it only between calls into the host, not from them.
    double pump();
    /// How many simulations play.
    int playing() const;
    /// Pauses every playing simulation (a console's Ctrl-C); returns how many it paused.
    /// An interrupt pauses them too, at the next pump(): a console that clears interrupts at
    /// its prompt calls pump() or this first.
    int pause_all();
    /// The wall clock simulations play against, in seconds from any origin (default:
    /// std::chrono::steady_clock); tests pass a fake one.
    void set_clock(std::function<double()> now);
    /// Wall seconds of work one pump() does at most (default 0.02).
    void set_pump_slice(double seconds);
    /// Calls `fn` while a sim:run or sim:step takes long: first after 0.5 s of wall time,
    /// then every 0.25 s at most, and once with `done` at its end if it was called; also with
    /// `done` before the script prints to stdout while the run goes on (a front end that shows
    /// a progress line takes it away). `fn` must not throw. An empty `fn`: no progress.
    void set_progress(std::function<void(const RunProgress&)> fn);

    /// Loads and runs a Lua file; throws ScriptError (syntax or runtime).
    void run_file(const std::string& path);
    /// Loads and runs a string; `name` is the chunk name shown in messages.
    void run_string(const std::string& code, const std::string& name);
    /// Loads a simulation file and the parts it names, runs it for its duration and prints how
    /// far each robot moved (`gaitlab run FILE.xml`); throws ScriptError.
    void run_simulation_file(const std::string& path);
    /// The accuracy check of a simulation file (`gaitlab check FILE.xml`): loads it, runs
    /// sim:check_accuracy (docs/lua-api.md) for `seconds` (0: the file's duration) sampled every
    /// `cycle` seconds (0: the check's default) from `settle` on, prints a line per robot and
    /// reports the warnings; returns how many settings were warned. Throws ScriptError.
    int check_simulation_file(const std::string& path, double seconds, double cycle, double settle);

  private:
    struct Memory;
    std::unique_ptr<Memory> memory_;  // the allocator's state: outlives L_
    lua_State* L_;
    Guard* guard_;  // L_'s limits, found once: interrupt() must not touch the Lua state
};

}  // namespace gaitlab::scripting
