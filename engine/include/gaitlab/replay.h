// Replaying the events of a recorded run: the changes that did not come from the script
// (console, viewer, hot reload from disk) are applied again at their ticks, and the changes the
// script makes are checked against the recorded ones. The script itself is rerun by the
// scripting layer (gaitlab/scripting/replay.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gaitlab/error.h"
#include "gaitlab/event.h"

namespace gaitlab {

class Simulation;

/// Thrown from the simulation's pre-tick point when a replay has reached the last tick the
/// run recorded (replays of runs that did not finish stop there).
class ReplayEnd : public Error {
  public:
    using Error::Error;
};

class EventReplay {
  public:
    /// Applies a recorded event the engine cannot apply itself (a reload of controller code);
    /// throws to report that it cannot.
    using Apply = std::function<void(Simulation&, const Event&)>;

    /// Attaches to `sim` (which must outlive this object). `events` are the run's, in order;
    /// `stop_tick` >= 0 ends the replay (ReplayEnd) before the tick that would go past it.
    EventReplay(Simulation& sim, std::vector<Event> events, Apply apply_other = {},
                long stop_tick = -1);
    ~EventReplay();
    EventReplay(const EventReplay&) = delete;
    EventReplay& operator=(const EventReplay&) = delete;

    /// Applies the events due now (the pre-tick point calls this; also call it when the
    /// script has finished, for events after the last step).
    void apply_due();
    /// The first way the replay departed from the recorded events ("" if none).
    const std::string& divergence() const { return divergence_; }
    /// Events applied from the recording (not made by the script).
    int applied() const { return applied_; }
    /// Recorded events matched so far (applied or made again by the script).
    size_t matched() const { return next_; }
    /// Whether the replay stopped at stop_tick.
    bool ended() const { return ended_; }
    /// Calls `fn` when the replay reaches stop_tick, just before ReplayEnd is thrown: a host
    /// whose code could catch ReplayEnd (a script's pcall around sim:run) stops that code here.
    void on_end(std::function<void()> fn) { on_end_ = std::move(fn); }
    /// Stops following the simulation (its recording stopped); the results stay.
    void detach();

  private:
    void on_event(const Event& e);
    void diverge(std::string message);
    static std::string describe(const Event& e);

    Simulation& sim_;
    std::vector<Event> events_;
    Apply apply_other_;
    std::function<void()> on_end_;
    long stop_tick_;
    size_t next_ = 0;
    int applied_ = 0;
    bool applying_ = false;
    bool ended_ = false;
    std::string divergence_;
    int hook_ = 0;
    int listener_ = 0;
    bool attached_ = true;
};

}  // namespace gaitlab
