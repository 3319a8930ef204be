// The accuracy check: whether a world's robots move as fast with finer numerical settings.
// It runs the world three times from time 0 — at the given options, at a quarter of the time
// step (the control period kept), and with four times the solver iterations — and compares
// each robot's path: its centre of mass on the floor plane, sampled once per cycle of its gait
// (so the to and fro within a cycle does not count), the measure of the convergence table of
// docs/performance.md. A path more than 3 % longer or shorter under a finer setting gets a
// warning naming that setting: the robot's speed then depends on the setting, not only on the
// physics. Where the robots end up and how far they turned are reported, not judged: on a long
// chain the heading wanders with any change to the run, the finest settings' included.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gaitlab/options.h"
#include "gaitlab/types.h"
#include "gaitlab/world.h"

namespace gaitlab {

class Simulation;

/// Where one robot ended up in one run of the check.
struct AccuracyRun {
    double path = 0;    ///< its path sampled once per cycle after the settling time, m
    Vec3 displacement;  ///< its centre of mass minus its start, m
    double turned = 0;  ///< how far it turned, rad (Simulation::robot_turned)
};

/// One robot's three runs, and how far the finer ones moved it.
struct AccuracyRobot {
    std::string name;  ///< its label in the simulation
    AccuracyRun given, finer_dt, more_iterations;
    /// the given run's path minus the finer one's, in % of the finer one's (of 1 mm where it
    /// is shorter)
    double dt_off = 0, iterations_off = 0;
};

/// What check_accuracy found.
struct AccuracyReport {
    double seconds = 0;
    double cycle = 0;   ///< s between the path's samples
    double settle = 0;  ///< s before the first sample
    SimulationOptions given, finer_dt, more_iterations;
    bool dt_checked = true;  ///< false where dt / 4 is below the smallest dt (1 µs)
    std::vector<AccuracyRobot> robots;
    /// one per setting that moved a robot by more than kAccuracyTolerance, naming the setting,
    /// the robot that moved most and by how much
    std::vector<std::string> warnings;
};

/// The tolerance of the check, %: issue 14's point 2 for the standard gaits.
inline constexpr double kAccuracyTolerance = 3.0;

/// Runs `world` for `seconds` from time 0 at `options`, at dt / 4 (control_every x 4) and at
/// solver_iterations x 4, and compares each robot's path sampled every `cycle` seconds (the
/// gait's cycle) from `settle` seconds on (the start's transient left out; 0 keeps it): the
/// samples are at the ticks nearest to settle + k cycle, and at the end.
/// `world`'s controllers that drive another simulation are copied fresh (Simulation's
/// constructor), so a running simulation's world() can be checked without disturbing it.
/// `prepare`, if given, is called on each of the three simulations before it runs (a host adds
/// its interrupt check or error handler there). Throws SpecError for options, a `seconds` (> 0,
/// its ticks at dt / 4 within kMaxTicks), a `settle` (in [0, seconds)) or a `cycle` (in [dt,
/// seconds - settle]) out of range, and whatever building or running a simulation throws (a
/// controller's error under ControllerErrorPolicy::stop).
AccuracyReport check_accuracy(const WorldSpec& world, const SimulationOptions& options,
                              double seconds, double cycle, double settle,
                              const std::function<void(Simulation&)>& prepare = {});

}  // namespace gaitlab
