// Evaluating lists of parameter sets on worker threads, a Lua state each (see
// gaitlab/optimize/runner.h).
#include <chrono>
#include <condition_variable>
#include <limits>
#include <thread>

#include "gaitlab/optimize/runner.h"

namespace gaitlab::optimize {

// a signal (stop) interrupts the evaluations under way: watched from a thread of its own
struct EvaluationPool::Watcher {
    std::mutex mutex;
    std::condition_variable wake;
    bool done = false;
    std::thread thread;
    ~Watcher() {
        {
            std::lock_guard<std::mutex> lock(mutex);
            done = true;
        }
        wake.notify_all();
        if (thread.joinable()) thread.join();
    }
};

EvaluationPool::EvaluationPool(const Spec& spec, int workers, std::uint64_t seed,
                               const std::atomic<int>* stop)
    : pool_(workers) {
    for (int w = 0; w < workers; ++w)
        evaluators_.push_back(std::make_unique<Evaluator>(spec, seed));
    if (!stop) return;
    watcher_ = std::make_unique<Watcher>();
    Watcher* w = watcher_.get();
    w->thread = std::thread([this, w, stop] {
        std::unique_lock<std::mutex> lock(w->mutex);
        while (!w->done) {
            if (const int sig = stop->load(); sig != 0) {
                for (auto& e : evaluators_)
                    e->interrupt(sig);
                return;
            }
            w->wake.wait_for(lock, std::chrono::milliseconds(50));
        }
    });
}

EvaluationPool::~EvaluationPool() {
    watcher_.reset();  // joined before the evaluators go
}

std::vector<Evaluation> EvaluationPool::evaluate(const std::vector<std::vector<double>>& xs,
                                                 const std::function<void(double)>& on_each) {
    return pool_.evaluate(xs, [&](const std::vector<double>& x, int worker) {
        // on_each is told the fitness, or NaN when the evaluation throws (and still throws)
        double fitness = std::numeric_limits<double>::quiet_NaN();
        struct Each {
            std::mutex& m;
            const std::function<void(double)>& fn;
            const double& fitness;
            ~Each() {
                if (!fn) return;
                std::lock_guard<std::mutex> lock(m);
                fn(fitness);
            }
        } each{each_mutex_, on_each, fitness};
        fitness = evaluators_[static_cast<std::size_t>(worker)]->evaluate(x);
        return fitness;
    });
}

}  // namespace gaitlab::optimize
