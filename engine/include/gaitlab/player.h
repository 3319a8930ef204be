// Playing a simulation against the wall clock: real time × speed, with an adjustable delay
// between physics steps, in bounded slices of work, so that a console (or a viewer) can step it
// between keystrokes on the thread that owns it. No threads here: whoever plays the simulation
// calls advance() again when wait() says.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>

namespace gaitlab {

class Simulation;

/// A monotonic wall clock, seconds from any origin (tests pass a fake one).
using WallClock = std::function<double()>;

/// std::chrono::steady_clock, in seconds.
double steady_seconds();

/// The longest delay between two physics steps, s.
inline constexpr double kMaxPlayDelay = 10;
/// How far behind its pace a player may fall, in wall seconds, before it stops trying to catch
/// up (it then paces from where it is: a slow simulation runs as fast as it can, no faster).
inline constexpr double kMaxPlayLag = 0.25;

class Player {
  public:
    /// A paused player of `sim` (kept alive as long as the player).
    explicit Player(std::shared_ptr<Simulation> sim);
    ~Player();
    Player(const Player&) = delete;
    Player& operator=(const Player&) = delete;

    Simulation& simulation() const { return *sim_; }

    bool playing() const { return playing_; }
    /// Plays from wall time `now` on: the simulation time advances by (now' - now) × speed,
    /// less one delay per tick. No-op if it plays already.
    void play(double now);
    void pause() { playing_ = false; }

    /// Target real-time factor, in (0, +inf] (+inf: as fast as the work slices allow); SpecError
    /// otherwise. Default 1. Takes effect from the next advance (the pace restarts there).
    void set_speed(double speed);
    double speed() const { return speed_; }
    /// Wall seconds added between two physics steps, in [0, kMaxPlayDelay]; SpecError
    /// otherwise. Default 0.
    void set_delay(double seconds);
    double delay() const { return delay_; }

    /// Runs, one tick at a time, the ticks due by clock() while it plays, until clock() reaches
    /// `deadline` (one tick at least, if one is due). A simulation stepped, run or reset by
    /// someone else since the last call paces from where it is now; one that is more than
    /// kMaxPlayLag behind after the call does too. Pauses when a controller fails under
    /// ControllerErrorPolicy::pause; an exception from Simulation::step pauses it and
    /// propagates. Returns the ticks run.
    long advance(const WallClock& clock, double deadline);
    /// Wall seconds from `now` until the next tick is due: 0 when one is due (always, at
    /// speed +inf without a delay), +inf when paused.
    double wait(double now) const;

    /// The real-time factor measured while playing: simulated seconds per wall second over the
    /// last half second or more; NaN until a first measure since play().
    double measured_speed() const { return measured_; }

    /// Why the simulation must be reset before it plays again ("" if it need not): set by the
    /// caller that caught a failure (a diverged step), cleared by the simulation's reset.
    const std::string& failure() const { return failure_; }
    /// Pauses and records `why` as the failure.
    void fail(std::string why);

  private:
    static constexpr double kInf = std::numeric_limits<double>::infinity();
    // wall seconds per tick at this speed and delay (0: as fast as possible)
    double period() const;
    // the ticks due by wall time `now`
    long due(double now) const;
    // paces from here: `now` is the wall time of the current tick count
    void rebase(double now);
    void measure(double now);

    std::shared_ptr<Simulation> sim_;
    int listener_ = 0;
    bool playing_ = false;
    double speed_ = 1;
    double delay_ = 0;
    bool rebase_pending_ = false;
    double base_wall_ = 0;  // wall time at which the simulation had base_ticks_ ticks
    long base_ticks_ = 0;
    long last_ticks_ = 0;  // tick count after the last advance
    double window_wall_ = 0;
    double window_time_ = 0;
    double measured_ = std::numeric_limits<double>::quiet_NaN();
    std::string failure_;
};

}  // namespace gaitlab
