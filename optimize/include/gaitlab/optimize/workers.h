// Evaluating a generation on N threads. Each individual is evaluated once, by whichever worker
// is free; the results are stored by individual, never by arrival, so the outcome of a run
// does not depend on the number of workers or on timing. A worker's number is passed to the
// evaluation so that each worker can own its own simulation and Lua state.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "gaitlab/optimize/method.h"

namespace gaitlab::optimize {

/// The outcome of one evaluation.
struct Evaluation {
    double fitness = 0.0;  ///< the value returned; NaN when the evaluation failed
    std::string error;     ///< why it failed (the exception's message); empty when it did not
    double seconds = 0.0;  ///< wall-clock time the evaluation took, s
    int worker = -1;       ///< the worker that ran it, in [0, workers) (of its rank)
    int rank = -1;         ///< the MPI rank that ran it; -1: this process
    bool failed() const { return !error.empty(); }
};

/// Evaluates one individual (parameter units) on worker `worker` and returns its fitness. An
/// exception, or a result that is NaN or infinite, marks the individual failed.
using EvaluateFunction = std::function<double(const std::vector<double>& x, int worker)>;

/// Called after each evaluation of a batch, one call at a time: the individual's index in the
/// batch and its result.
/// Evaluates `x` as a WorkerPool's worker does: the fitness, or the message of what failed (an
/// exception, a result that is not finite: fitness NaN), and the seconds it took.
Evaluation evaluate_one(const EvaluateFunction& evaluate, const std::vector<double>& x, int worker);

using EvaluationDone = std::function<void(std::size_t individual, const Evaluation& result)>;

/// A fixed set of worker threads that evaluate generations.
class WorkerPool {
  public:
    /// Starts `workers` threads (>= 1; Error otherwise).
    explicit WorkerPool(int workers);
    /// Stops and joins the threads.
    ~WorkerPool();
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    int workers() const { return static_cast<int>(threads_.size()); }

    /// Evaluates every individual of `xs` with `evaluate`, spread over the workers; returns
    /// when all are done, result i for individual i. One call at a time: a call while another
    /// is under way (from another thread, or from inside an evaluation) throws Error.
    /// `on_done` (if set) is called after each evaluation, one call at a time.
    std::vector<Evaluation> evaluate(const std::vector<std::vector<double>>& xs,
                                     const EvaluateFunction& evaluate,
                                     const EvaluationDone& on_done = {});

  private:
    void work(int worker);

    std::vector<std::thread> threads_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::condition_variable done_;
    // the batch under way: read by the workers while `remaining_` > 0
    const std::vector<std::vector<double>>* xs_ = nullptr;
    const EvaluateFunction* evaluate_ = nullptr;
    const EvaluationDone* on_done_ = nullptr;
    std::vector<Evaluation>* results_ = nullptr;
    std::size_t next_ = 0;
    std::size_t remaining_ = 0;
    std::uint64_t batch_ = 0;
    bool stop_ = false;
};

/// What optimize() reports after each generation.
struct GenerationReport {
    int generation = 0;  ///< the generation just told, from 0
    const std::vector<std::vector<double>>* individuals = nullptr;  ///< as asked
    const std::vector<Evaluation>* evaluations = nullptr;           ///< one per individual
};

/// Runs `generations` generations of `method` with `pool` and `evaluate`, calling `on_generation`
/// (if set) after each. The method's best() is the result.
void optimize(Method& method, WorkerPool& pool, const EvaluateFunction& evaluate, int generations,
              const std::function<void(const GenerationReport&)>& on_generation = {});

}  // namespace gaitlab::optimize
