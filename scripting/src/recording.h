// The recordings of one Lua state: which simulations record where (the host's settings and what
// scripts ask for), the configuration copied into their run folders (the script and the
// controller files with every version that ran), the log lines they get (print, reports), and
// replay mode, where the simulation being replayed records into the replay's folder while the
// recorded changes from outside the script are applied again.
#pragma once

#include <lua.hpp>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gaitlab/player.h"
#include "gaitlab/recorder.h"
#include "gaitlab/replay.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/simulation.h"
#include "gaitlab/xml.h"

namespace gaitlab::scripting {

class Guard;
struct WorldBinding;
struct RobotBinding;

/// Adds a line to the logs of the open recordings of L (nothing if there are none).
void log_to_recordings(lua_State* L, const std::string& line);

/// The path a binding reads for the file `arg` that a script names (relative to the script's
/// folder): noted as an input of the run folders, and in a replay the run folder's copy.
std::string input_path(lua_State* L, const std::string& arg);

/// "SIGTERM" for SIGTERM ...; "signal N" for a signal without a name here.
std::string signal_name(int signal);

/// The "signal" a replay interrupts its script with when it reaches the end of the run it
/// replays (no real signal has this number).
inline constexpr int kReplayEndSignal = 1 << 20;

/// A simulation as Lua holds it (the gaitlab.Simulation userdata).
struct SimulationHandle {
    std::shared_ptr<Simulation> sim;
    int index = 0;  ///< 1-based creation order in this Lua state
    std::shared_ptr<Recorder> recorder;
    std::shared_ptr<WorldBinding> world;  ///< what it was compiled from (for sim:save)
    std::shared_ptr<Player> player;       ///< plays it against the wall clock (sim:play())
    /// sim:robot(name)'s handles, per robot, made when the world's robot handle is not this
    /// simulation's robot (an older simulation of the world, once a later one is built; a
    /// clone)
    std::vector<std::shared_ptr<RobotBinding>> robots;
    /// What sim:save writes besides the world (gaitlab.simulation{ name, duration, record }):
    /// the name ("" : the saved file's stem), the duration (unset: the time simulated so far)
    /// and the recording settings
    std::string name;
    std::optional<double> duration;
    RecordSpec record;
};

/// What a script asks for with `record = ...` or sim:record(...).
struct RecordRequest {
    enum class Mode { absent, off, on } mode = Mode::absent;
    std::string dir;  ///< "" : the host's choice
    RecordOptions options;
};

/// What replaying a run needs and finds out (scripting/src/replay.cpp fills it).
struct ReplayPlan {
    std::string into;                       ///< the replay's run folder
    int simulation = 1;                     ///< which simulation of the script to record
    std::string started_by = "simulation";  ///< when the run's recording started
    RecordOptions options;                  ///< record_every, flush_seconds, series
    SimulationOptions expect;               ///< the run's simulation options
    std::vector<Event> events;
    long stop_tick = -1;  ///< >= 0: the run did not finish; stop after its last row
    std::vector<std::string> controller_sources;  ///< load order
    std::vector<std::string> controller_paths;    ///< config paths, load order
    std::map<std::pair<size_t, std::uint64_t>, std::string> reload_sources;
    /// files the run read (robots, images ...): original path -> their copy in the run folder
    std::map<std::string, std::string> inputs;

    // found out while replaying
    std::shared_ptr<Simulation> sim;
    std::shared_ptr<Recorder> recorder;
    std::unique_ptr<EventReplay> replay;
    std::string mismatch;  ///< the replayed simulation is not the recorded one
};

class Recordings {
  public:
    /// The recordings of the Lua state (created by open_simulation).
    static Recordings& of(lua_State* L);
    static void install(lua_State* L);

    RecordSettings settings;
    std::string script_source;  ///< the code of settings.script as it ran
    std::uint64_t script_seed = 0;
    std::vector<std::string> script_args;
    bool print_to_stdout = true;
    /// where print() writes instead of stdout when set (LuaHost::set_output)
    std::function<void(const std::string&)> output;
    std::shared_ptr<ReplayPlan> replay;  ///< set in replay mode
    std::vector<std::function<void(Simulation&, int)>> on_created;

    /// A new simulation: gives it its index, records it if asked, calls on_created.
    void created(lua_State* L, SimulationHandle& h, const RecordRequest& request);
    /// sim:record(...): starts recording now; returns the folder, or "" if the host or replay
    /// mode records nothing here. Throws Error if it already records.
    std::string start(lua_State* L, SimulationHandle& h, const RecordRequest& request);
    /// sim:record(false): stops recording (closed as finished).
    void stop(SimulationHandle& h);

    /// A file the script has gaitlab read (a robot, URDF, environment, actuation, image ...):
    /// copied into the run folders' config/ (where the script's folder has it, or under
    /// external/ + its absolute path), so a replay reads the same bytes. Files that cannot be
    /// read are left to the reader to report.
    void on_input(const std::string& path);
    /// The path to read for `path` (absolute): in a replay, the run folder's copy of a file
    /// outside the script's folder; otherwise `path`.
    std::string input_path(const std::string& path) const;

    std::vector<std::string> folders() const { return folders_; }
    /// Closes every open recording: "interrupted" (naming the signal) if the Lua state was
    /// interrupted (LuaHost::interrupt), else "failed" with `error` if it is not empty, else
    /// "finished".
    void finish(const std::string& error);
    /// Adds a line to the log of every open recording.
    void log_line(const std::string& line);

  private:
    // records `h` into `dir` (the host's choice when empty)
    std::string begin(lua_State* L, SimulationHandle& h, const RecordRequest& request,
                      const std::string& started_by);
    void begin_replay(lua_State* L, SimulationHandle& h, const std::string& started_by);
    RunContext context(lua_State* L, int index, const std::string& started_by) const;
    std::string next_dir();
    // a controller file's path inside config/
    std::string config_path(size_t index, const std::string& chunk) const;
    // where version `version` of controller file `index` (at config path `path`) goes
    static std::string reload_path(size_t index, const std::string& path, std::uint64_t version);
    // a controller file loaded (version 0) or reloaded: copied into the open run folders; a
    // reload is also an event of every simulation
    void on_file(size_t index, const std::string& chunk, const std::string& source,
                 std::uint64_t version, Origin origin);

    // the folder `dir` (absolute and normalized), if no simulation of this state recorded
    // into it yet; else IoError
    std::string claim(const std::string& dir, int index) const;

    // the inputs read so far, in order (config file role "input")
    std::vector<ConfigFile> inputs_;
    int created_ = 0;
    int dirs_ = 0;
    std::vector<std::string> folders_;
    // every folder a simulation of this state recorded into: (absolute path, simulation)
    std::vector<std::pair<std::string, int>> claimed_;
    std::vector<std::weak_ptr<Recorder>> recorders_;
    Guard* guard_ = nullptr;  // the state's interrupts
    std::vector<std::weak_ptr<Simulation>> sims_;
};

}  // namespace gaitlab::scripting
