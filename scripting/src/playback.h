// How the simulations of one Lua state advance against the wall clock: the players of those a
// script set playing (sim:play(), stepped by LuaHost::pump between a console's keystrokes),
// the clock they pace against, and the progress hook of long sim:run / sim:step calls.
#pragma once

#include <lua.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gaitlab/player.h"
#include "gaitlab/scripting/lua_host.h"

namespace gaitlab::scripting {

struct SimulationHandle;

class ProgressScope;

class Playback {
  public:
    /// The playback of the Lua state (created by open_simulation).
    static Playback& of(lua_State* L);
    static void install(lua_State* L);

    WallClock clock = steady_seconds;  ///< what players pace against
    double slice = 0.02;               ///< wall seconds of work per pump at most
    /// Where long runs report their progress (none: they do not).
    std::function<void(const RunProgress&)> progress;
    /// How sim:run and sim:step advance (LuaHost::set_runner); empty: Simulation::step.
    LuaHost::Runner runner;
    /// What sim:view() calls (LuaHost::set_view_handler); empty: sim:view() is an error.
    LuaHost::ViewHandler view;
    /// What gaitlab.optimize{} calls (LuaHost::set_optimize_handler); empty: it is an error.
    LuaHost::OptimizeHandler optimize;
    /// Called with every new simulation's player (LuaHost::on_player).
    std::vector<std::function<void(const std::shared_ptr<Player>&, int)>> on_player;

    /// sim:play(): plays the simulation of `h` from now on (it keeps playing while the
    /// handle is gone). Throws Error if it failed and must be reset first.
    void play(SimulationHandle& h);
    /// How many simulations play.
    int playing() const;
    /// See LuaHost::pump; L is the state's main thread.
    double pump(lua_State* L);
    /// Called before the script writes to stdout: a progress line on the terminal goes first.
    void before_output() const;
    /// Pauses every playing simulation, reporting "simulation N paused at t = T s: WHY" for
    /// each unless `why` is empty.
    void pause_all(lua_State* L, const std::string& why);

  private:
    friend class ProgressScope;
    struct Entry {
        std::shared_ptr<Player> player;
        int index;  // the simulation's creation index, for messages
    };
    std::vector<Entry> playing_;
    size_t next_ = 0;  // who starts the next pump: each in turn gets the first share
    bool pumping_ = false;
    ProgressScope* active_ = nullptr;  // the innermost run with a progress line
};

/// Reports the progress of a sim:run or sim:step of `sim` to the host's hook while it lives.
class ProgressScope {
  public:
    ProgressScope(lua_State* L, Simulation& sim, double end_time);
    ~ProgressScope();
    ProgressScope(const ProgressScope&) = delete;
    ProgressScope& operator=(const ProgressScope&) = delete;

  private:
    friend class Playback;
    // tells the hook to take the line away (it comes back at the next update)
    void hide();
    Playback& playback_;
    Simulation& sim_;
    bool active_ = false;  // the host has a progress hook
    ProgressScope* outer_ = nullptr;
    int observer_ = 0;
    double start_wall_ = 0;
    double next_ = 0;  // wall time of the next update
    RunProgress last_;
    bool shown_ = false;
};

}  // namespace gaitlab::scripting
