#include "gaitlab/options.h"

#include <cmath>
#include <iterator>
#include <string>

#include <fmt/format.h>

#include "gaitlab/checked.h"
#include "gaitlab/error.h"
#include "spec/check.h"

namespace gaitlab {

void validate(const SimulationOptions& o) {
    detail::check_range("dt", o.dt, 1e-6, 0.1, "s");
    checked_int("control_every", o.control_every, 1, kMaxControlEvery);
    checked_int("solver_iterations", o.solver_iterations, 1, kMaxSolverIterations);
    if (o.newton_steps != kAutomaticNewtonSteps)
        checked_int("newton_steps", o.newton_steps, 0, kMaxNewtonSteps);
    if (o.newton_steps > 0 && o.solver != ConstraintSolver::block_nncg) {
        throw SpecError(fmt::format(
            "newton_steps = {} needs solver = 'block_nncg' (got solver = '{}'; newton_steps "
            "must be 0 with it)",
            o.newton_steps, to_string(o.solver)));
    }
}

const char* to_string(ControllerErrorPolicy policy) {
    switch (policy) {
        case ControllerErrorPolicy::stop:
            return "stop";
        case ControllerErrorPolicy::continue_:
            return "continue";
        case ControllerErrorPolicy::pause:
            return "pause";
    }
    return "stop";
}

const char* to_string(ConstraintSolver solver) {
    return solver == ConstraintSolver::block_nncg ? "block_nncg" : "pgs";
}

namespace {
constexpr ConstraintSolver kSolvers[] = {ConstraintSolver::pgs, ConstraintSolver::block_nncg};
}  // namespace

bool parse_solver(std::string_view name, ConstraintSolver& solver) {
    for (ConstraintSolver c : kSolvers) {
        if (name == to_string(c)) {
            solver = c;
            return true;
        }
    }
    return false;
}

std::string solver_names() {
    std::string names;
    for (std::size_t i = 0; i < std::size(kSolvers); ++i) {
        if (i > 0) names += i + 1 == std::size(kSolvers) ? " or " : ", ";
        names += fmt::format("'{}'", to_string(kSolvers[i]));
    }
    return names;
}

long checked_ticks(std::string_view what, double seconds, double dt, long done) {
    if (!(std::isfinite(seconds) && seconds >= 0)) {
        throw SpecError(fmt::format("{} must be a non-negative number of seconds (got {})", what,
                                    detail::shown(seconds)));
    }
    // compared as doubles first: seconds / dt may be far beyond what a long holds
    const long left = kMaxTicks - done;
    const double n = std::round(seconds / dt);
    if (!(n <= static_cast<double>(left))) {
        throw SpecError(fmt::format("{} must be in [0, {:g}] s at dt = {:g} s (got {:g} s)", what,
                                    static_cast<double>(left) * dt, dt, seconds));
    }
    return static_cast<long>(n);
}

}  // namespace gaitlab
