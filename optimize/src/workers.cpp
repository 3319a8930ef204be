#include "gaitlab/optimize/workers.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "gaitlab/error.h"

namespace gaitlab::optimize {

WorkerPool::WorkerPool(int workers) {
    if (workers < 1) throw Error(fmt::format("workers must be at least 1 (got {})", workers));
    threads_.reserve(static_cast<std::size_t>(workers));
    for (int w = 0; w < workers; ++w)
        threads_.emplace_back([this, w] { work(w); });
}

WorkerPool::~WorkerPool() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_)
        t.join();
}

std::vector<Evaluation> WorkerPool::evaluate(const std::vector<std::vector<double>>& xs,
                                             const EvaluateFunction& evaluate,
                                             const EvaluationDone& on_done) {
    std::vector<Evaluation> results(xs.size());
    if (xs.empty()) return results;
    std::unique_lock<std::mutex> lock(mutex_);
    // a second batch (from another thread, or from inside an evaluation) would wait for the
    // workers the first one holds: refused instead of a deadlock
    if (xs_) throw Error("WorkerPool::evaluate: a batch is already under way (one call at a time)");
    xs_ = &xs;
    evaluate_ = &evaluate;
    on_done_ = on_done ? &on_done : nullptr;
    results_ = &results;
    next_ = 0;
    remaining_ = xs.size();
    ++batch_;
    wake_.notify_all();
    done_.wait(lock, [this] { return remaining_ == 0; });
    xs_ = nullptr;
    evaluate_ = nullptr;
    on_done_ = nullptr;
    results_ = nullptr;
    return results;
}

Evaluation evaluate_one(const EvaluateFunction& evaluate, const std::vector<double>& x,
                        int worker) {
    Evaluation e;
    e.worker = worker;
    const auto start = std::chrono::steady_clock::now();
    try {
        e.fitness = evaluate(x, worker);
        if (!std::isfinite(e.fitness))
            e.error = fmt::format("the fitness is {} (expected a finite number)", e.fitness);
    } catch (const std::exception& ex) {
        e.error = ex.what();
        if (e.error.empty()) e.error = "the evaluation failed (an exception without a message)";
    } catch (...) {
        e.error = "the evaluation failed (an exception that is not a std::exception)";
    }
    if (!e.error.empty()) e.fitness = std::numeric_limits<double>::quiet_NaN();
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return e;
}

void WorkerPool::work(int worker) {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        wake_.wait(lock, [this] { return stop_ || (xs_ && next_ < xs_->size()); });
        if (stop_) return;
        // take the next individual; its result goes to its own slot, whatever finishes first
        const std::size_t i = next_++;
        const std::vector<double>& x = (*xs_)[i];
        const EvaluateFunction& f = *evaluate_;
        lock.unlock();
        Evaluation e = evaluate_one(f, x, worker);
        lock.lock();
        (*results_)[i] = std::move(e);
        if (on_done_) {
            try {
                (*on_done_)(i, (*results_)[i]);
            } catch (...) {
                // a report that fails must not take the worker down: the result is kept
            }
        }
        if (--remaining_ == 0) done_.notify_all();
    }
}

void optimize(Method& method, WorkerPool& pool, const EvaluateFunction& evaluate, int generations,
              const std::function<void(const GenerationReport&)>& on_generation) {
    if (generations < 0)
        throw Error(fmt::format("generations must be at least 0 (got {})", generations));
    for (int g = 0; g < generations; ++g) {
        const std::vector<std::vector<double>> individuals = method.ask();
        const std::vector<Evaluation> evaluations = pool.evaluate(individuals, evaluate);
        std::vector<double> fitness;
        fitness.reserve(evaluations.size());
        for (const Evaluation& e : evaluations)
            fitness.push_back(e.fitness);
        GenerationReport report;
        report.generation = method.generation();
        report.individuals = &individuals;
        report.evaluations = &evaluations;
        method.tell(fitness);
        if (on_generation) on_generation(report);
    }
}

}  // namespace gaitlab::optimize
