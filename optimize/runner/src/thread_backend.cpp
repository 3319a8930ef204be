// The thread backend: a WorkerPool whose workers each own an Evaluator (see backend.h).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>

#include "gaitlab/error.h"
#include "gaitlab/optimize/backend.h"
#include "gaitlab/optimize/runner.h"
#include "worker_state.h"

namespace gaitlab::optimize {

WorkerStates::WorkerStates(const Spec& spec, int workers, std::uint64_t seed)
    : spec_(spec), seed_(seed) {
    for (int w = 0; w < workers; ++w)
        evaluators_.push_back(std::make_unique<Evaluator>(spec_, seed_));
}

double WorkerStates::evaluate(const std::vector<double>& x, int worker) {
    Evaluator* evaluator = nullptr;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        evaluator = evaluators_[static_cast<std::size_t>(worker)].get();
    }
    try {
        return evaluator->evaluate(x);
    } catch (...) {
        renew(worker);
        throw;
    }
}

Evaluation WorkerStates::run(const std::vector<double>& x, int worker) {
    return evaluate_one([this](const std::vector<double>& p, int w) { return evaluate(p, w); }, x,
                        worker);
}

void WorkerStates::renew(int worker) {
    std::unique_ptr<Evaluator> fresh;
    try {
        fresh = std::make_unique<Evaluator>(spec_, seed_);
    } catch (const std::exception&) {
        // the spec loaded before and does not now (its file changed): the old state goes on
        return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (signal_ != 0) fresh->interrupt(signal_);
    evaluators_[static_cast<std::size_t>(worker)].swap(fresh);
    // `fresh`, the old state, is closed here: no other thread uses a worker's evaluator
}

void WorkerStates::interrupt(int signal) {
    std::lock_guard<std::mutex> lock(mutex_);
    signal_ = signal;
    for (auto& e : evaluators_)
        e->interrupt(signal);
}

namespace {

class ThreadBackend : public EvaluationBackend {
  public:
    ThreadBackend(const Spec& spec, int workers, std::uint64_t seed)
        : states_(spec, workers, seed), pool_(workers) {}

    int workers() const override { return pool_.workers(); }

    std::string describe() const override {
        return fmt::format("{} worker{}", workers(), workers() == 1 ? "" : "s");
    }

    std::vector<Evaluation> evaluate(const std::vector<std::vector<double>>& xs,
                                     const EvaluationDone& on_done) override {
        return pool_.evaluate(
            xs,
            [this](const std::vector<double>& x, int worker) {
                return states_.evaluate(x, worker);
            },
            on_done);
    }

    void interrupt(int signal) override { states_.interrupt(signal); }

  private:
    WorkerStates states_;
    WorkerPool pool_;
};

}  // namespace

std::unique_ptr<EvaluationBackend> make_thread_backend(const Spec& spec, int workers,
                                                       std::uint64_t seed) {
    if (workers < 1) {
        throw SpecError(fmt::format("--workers: a whole number >= 1 expected, got {}", workers));
    }
    return std::make_unique<ThreadBackend>(spec, workers, seed);
}

}  // namespace gaitlab::optimize
