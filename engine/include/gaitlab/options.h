// Simulation options: a plain value like the specs (a simulation file stores them, and
// compiling a simulation checks them), and the limits of run lengths. simulation.h includes
// this header, so a program that builds a Simulation needs no other.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace gaitlab {

/// What a simulation does when a controller's step throws.
enum class ControllerErrorPolicy {
    stop,       ///< the error leaves Simulation::step (batch runs)
    continue_,  ///< the controller is marked failed, its group holds, the run goes on
    pause       ///< as continue_, but step/run return at the end of that tick (consoles)
};

/// "stop", "continue" or "pause".
const char* to_string(ControllerErrorPolicy policy);

/// How the constraint solver iterates (docs/architecture.md, "Physics formulation").
enum class ConstraintSolver {
    pgs,         ///< Bullet's sequential impulses (projected Gauss-Seidel), one row at a time
    block_nncg,  ///< each robot's joints and motors solved exactly as one system in every
                 ///< iteration, contacts warm-started, with a nonlinear conjugate-gradient step
                 ///< after each: the default; converges in far fewer iterations on chains
                 ///< pressed onto the floor, about 1.1-1.2x pgs's cost per step
};

/// "pgs" or "block_nncg".
const char* to_string(ConstraintSolver solver);
/// The solver `name` names ("pgs" or "block_nncg"); false if it names none.
bool parse_solver(std::string_view name, ConstraintSolver& solver);
/// The names parse_solver takes, for messages: "'pgs' or 'block_nncg'".
std::string solver_names();

/// Limits of simulation options and run lengths (docs/formats.md).
inline constexpr int kMaxControlEvery = 1000000;  ///< also the limit of a recording's every
inline constexpr int kMaxSolverIterations = 10000;
inline constexpr int kMaxNewtonSteps = 100;
/// A robot with pitch and yaw joints both and more than kLongChainJoints joints (a pitch-yaw
/// chain of 13 modules or more) needs a finer step and more iterations than the defaults: at
/// 16 modules its rolling gait moves up to 6 % faster or slower with 4x the iterations, and at
/// 16 and 32 modules its gaits settle into one of several motions, which the settings can
/// change (on the default floor; at 12 modules every standard gait stays within 1 %), and
/// dt <= kLongChainMaxDt with solver_iterations >= kLongChainIterations
/// (block_nncg) keep each of its motions within 3 % of a converged solver, and so do
/// newton_steps >= kLongChainNewtonSteps in place of the iterations (docs/performance.md,
/// section 12, "A floor dt 1 ms resolves"). A simulation warns outside them; gaitlab new offers
/// them.
inline constexpr int kLongChainJoints = 12;
inline constexpr double kLongChainMaxDt = 0.0005;  // s
inline constexpr int kLongChainIterations = 40;
/// (8 since 2026-11-30: 4 left the 32-module wave's upright motion at 60-80 iterations,
/// docs/performance.md, "8 Newton steps")
inline constexpr int kLongChainNewtonSteps = 8;
/// with newton_steps >= kLongChainNewtonSteps on a floor no stiffer than the default, dt up to
/// this keeps such a chain's motions within 2 % (docs/performance.md, "Upright or on its side")
inline constexpr double kLongChainNewtonMaxDt = 0.001;  // s
/// SimulationOptions::newton_steps' default: the simulation chooses for its world
/// (automatic_newton_steps): kLongChainNewtonSteps with block_nncg where a robot is a chain bent
/// in two planes of more than kLongChainJoints joints, 0 otherwise. Simulation::options() gives
/// the number chosen.
inline constexpr int kAutomaticNewtonSteps = -1;
/// ticks a simulation runs in all (2^53: time = ticks · dt stays exact, and a tick count is a
/// Lua integer and a double alike)
inline constexpr long kMaxTicks = 9007199254740992L;

/// The ticks `seconds` make at step `dt` (round(seconds / dt)), when they keep a run that has
/// done `done` ticks within kMaxTicks; otherwise SpecError "WHAT must be in [0, MAX] s at dt =
/// DT s (got SECONDS s)" (and for a negative or non-finite number). Never converts a value that
/// does not fit.
long checked_ticks(std::string_view what, double seconds, double dt, long done = 0);

/// Global options of a simulation.
struct SimulationOptions {
    double dt = 0.001;       ///< physics step, s, in [1e-6, 0.1]
    int control_every = 30;  ///< ticks between controller steps, in [1, kMaxControlEvery]
    /// constraint solver iterations per step, in [1, kMaxSolverIterations]; 20 keeps standard
    /// gaits within about 1% of
    /// a converged solution and resting robots still (see docs/performance.md)
    int solver_iterations = 20;
    /// how the solver iterates over the rows (ConstraintSolver above)
    ConstraintSolver solver = ConstraintSolver::block_nncg;
    /// semi-smooth Newton steps on the whole step's contact problem after block_nncg's
    /// iterations, in [0, kMaxNewtonSteps], or kAutomaticNewtonSteps (the default:
    /// kLongChainNewtonSteps, 8, for a world with a pitch-yaw chain of 13 modules or more, else
    /// 0); block_nncg only (0 with pgs). 0: none, the step is block_nncg's alone. 8 keep each
    /// motion of the long pitch-yaw chains within 2 % of a converged solver at 20 to 320
    /// iterations (4 did at 20 but not at 60-80), at about 3x the step's cost
    /// (docs/architecture.md, "Physics formulation"; docs/performance.md, "8 Newton steps").
    int newton_steps = kAutomaticNewtonSteps;
    std::uint64_t seed = 0;  ///< seeds everything random in the run
    /// In both cases the failed controller is marked failed and its joints hold the angles
    /// measured when it failed (targets frozen) until reset().
    ControllerErrorPolicy on_controller_error = ControllerErrorPolicy::stop;
};

inline SimulationOptions default_simulation_options() {
    return SimulationOptions{};
}
/// Checks ranges; throws SpecError.
void validate(const SimulationOptions& options);

}  // namespace gaitlab
