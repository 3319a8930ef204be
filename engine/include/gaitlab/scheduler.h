// The fixed-step scheduler. One tick runs, in this order and no other:
//
//   1. sense    read the joints (every tick)
//   2. think    run the controllers (only when tick % control_every == 0)
//   3. act      servo law: turn targets into motor commands (every tick)
//   4. physics  one physics step of dt (every tick)
//   5. record   observers see the state after the step (every tick; each keeps its own rate)
//
// The time seen by sense/think/act is tick * dt before the step; record sees (tick + 1) * dt.
// The sensors a simulation reads for the sense phase are read as soon as the state they
// describe exists: at the start of record, before the observers (and when the simulation is
// built), so think, observers and callers between ticks all see readings of the current state.
#pragma once

namespace gaitlab {

/// The five phases of a tick, implemented by the simulation (or by a test).
class TickPhases {
  public:
    virtual ~TickPhases() = default;
    virtual void sense() = 0;
    /// `control_dt` = control_every * dt, the time since the previous think.
    virtual void think(double time, double control_dt) = 0;
    virtual void act() = 0;
    virtual void physics(double dt) = 0;
    virtual void record(long tick, double time) = 0;
};

class Scheduler {
  public:
    /// `dt` in s (> 0); `control_every` in ticks (>= 1).
    Scheduler(double dt, int control_every);

    /// Runs one tick of `phases`.
    void tick(TickPhases& phases) {
        const double now = time();
        phases.sense();
        if (ticks_ % control_every_ == 0) phases.think(now, control_dt_);
        phases.act();
        phases.physics(dt_);
        ++ticks_;
        phases.record(ticks_, time());
    }

    long ticks() const { return ticks_; }
    /// Simulated time, s: ticks * dt, so it never accumulates rounding error.
    double time() const { return static_cast<double>(ticks_) * dt_; }
    double dt() const { return dt_; }
    int control_every() const { return control_every_; }
    void reset() { ticks_ = 0; }
    /// Goes on from `ticks` ticks (a copy of a simulation at another dt: the same time).
    void set_ticks(long ticks) { ticks_ = ticks; }

  private:
    double dt_;
    int control_every_;
    double control_dt_;
    long ticks_ = 0;
};

}  // namespace gaitlab
