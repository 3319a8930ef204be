// The benchmark workload: a snake of N y1 modules on a flat floor, driven by sine gaits.
// Plain values only, so both the gaitlab side and the raw Bullet baseline read the same numbers.
#pragma once

#include <string>

#include "gaitlab/simulation.h"

namespace gaitlab_bench {

/// One benchmark scenario. The pitch joints follow a sine of `pitch_amplitude`, the yaw joints
/// (pitch-yaw chains only) one of `yaw_amplitude`; joint m of a group lags by m * phase.
struct Scenario {
    int modules = 8;
    bool pitch_yaw = false;          ///< false: pitch-pitch chain, true: pitch-yaw
    double pitch_amplitude = 40;     ///< deg
    double yaw_amplitude = 20;       ///< deg
    double frequency = 0.5;          ///< Hz
    double phase = 120;              ///< deg, between neighbours of a group
    double phase0 = 0;               ///< deg, added to every joint's sine (raw loop only)
    double yaw_phase0 = 0;           ///< deg, added to the yaw joints' sines too (raw loop only)
    bool friction_per_step = false;  ///< the solver's FrictionModel::per_step (raw loop only)
    /// the solver's SolverMethod (raw loop only): "pgs", "symmetric" or "nncg"
    std::string solver_method = "pgs";
    double floor_friction = 0.8;
    double dt = 0.001;       ///< s
    int control_every = 10;  ///< ticks between controller steps
    int solver_iterations = gaitlab::default_simulation_options().solver_iterations;
    double seconds = 20;  ///< simulated time
    /// built-in controller driving each group (gaitlab side only; the raw loop runs the sine);
    /// its amplitude, frequency and phase parameters are set when it has them
    std::string controller = "sine";
    /// sensors on the robot (gaitlab side only): "none"; "off" or "on": a joint, an IMU, a
    /// contact and a range sensor (looking down) on every module, and a position sensor, all
    /// switched off or on
    std::string sensors = "none";

    long ticks() const;
    /// "pp8 ce10", "py32 ce30 it50 dt0.1ms", ...
    std::string label() const;
};

}  // namespace gaitlab_bench
