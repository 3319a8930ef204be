// The Lua states of a process's workers, one Evaluator each (thread and MPI backends). A worker
// whose evaluation fails goes on in a fresh state: what the failed evaluation did to its state
// (a global removed, a table left half-changed) never reaches the next individual, so a run's
// result does not depend on which worker met the failure.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "gaitlab/optimize/runner.h"
#include "gaitlab/optimize/workers.h"

namespace gaitlab::optimize {

class WorkerStates {
  public:
    /// `workers` Evaluators of `spec` (each loads the spec file: throws as Evaluator does).
    /// `seed` seeds math.random before every evaluation (Evaluator).
    WorkerStates(const Spec& spec, int workers, std::uint64_t seed = 0);

    /// Evaluates `x` in worker `worker`'s state (from that worker's thread only); throws as
    /// Evaluator::evaluate, after giving the worker a fresh state.
    double evaluate(const std::vector<double>& x, int worker);

    /// Evaluates `x` in worker `worker`'s state as a WorkerPool does: the fitness, or the
    /// message of what failed (an exception, a result that is not finite), and the time taken.
    Evaluation run(const std::vector<double>& x, int worker);

    /// Interrupts every state, and the states made later (from any thread).
    void interrupt(int signal);

  private:
    void renew(int worker);

    Spec spec_;
    std::uint64_t seed_ = 0;
    std::mutex mutex_;  // guards the vector's slots against interrupt()
    std::vector<std::unique_ptr<Evaluator>> evaluators_;
    int signal_ = 0;
};

}  // namespace gaitlab::optimize
