// Evaluation backends: what evaluates a generation of individuals of a spec. run_optimization
// (and any other command that evaluates many parameter sets, such as a sweep) asks a backend
// for a batch and gets the results ordered by individual, never by arrival, so the outcome does
// not depend on the backend, the number of workers or timing. Two backends: threads in this
// process (make_thread_backend), and MPI ranks (gaitlab/optimize/mpi.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gaitlab/optimize/workers.h"

namespace gaitlab::optimize {

struct Spec;

class EvaluationBackend {
  public:
    virtual ~EvaluationBackend() = default;

    /// How many evaluations run at the same time (threads, over every rank).
    virtual int workers() const = 0;

    /// Who evaluates, for a progress line: "2 workers", "3 MPI ranks evaluating, 6 workers in
    /// all".
    virtual std::string describe() const = 0;

    /// Evaluates every individual of `xs` (parameter units, in spec order); returns when all
    /// are done, result i for individual i. A failed evaluation has its message in `error` and
    /// a NaN fitness. Throws Error when the batch cannot be finished (every MPI rank lost).
    virtual std::vector<Evaluation> evaluate(const std::vector<std::vector<double>>& xs,
                                             const EvaluationDone& on_done = {}) = 0;

    /// Stops the evaluations under way and every later one (they fail) as the signal would.
    /// Called from a thread other than the one in evaluate(); not from a signal handler.
    virtual void interrupt(int signal) = 0;
};

/// `workers` threads in this process (>= 1; SpecError otherwise), each with an Evaluator (its
/// own Lua state) of `spec`; `seed` seeds math.random before every evaluation. An evaluation that
/// fails leaves its Lua state behind: the worker goes on in a fresh one, so what a failed
/// evaluation did to its state (a global changed or removed) never reaches the next individual.
std::unique_ptr<EvaluationBackend> make_thread_backend(const Spec& spec, int workers,
                                                       std::uint64_t seed = 0);

}  // namespace gaitlab::optimize
