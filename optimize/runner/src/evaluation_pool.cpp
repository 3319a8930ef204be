// Evaluating lists of parameter sets on a backend: worker threads with a Lua state each, or
// MPI ranks (see gaitlab/optimize/runner.h).
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "gaitlab/optimize/backend.h"
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
                               const std::atomic<int>* stop, EvaluationBackend* backend)
    : backend_(backend) {
    if (!backend_) {
        own_ = make_thread_backend(spec, workers, seed);
        backend_ = own_.get();
    }
    if (!stop) return;
    watcher_ = std::make_unique<Watcher>();
    Watcher* w = watcher_.get();
    EvaluationBackend* b = backend_;
    w->thread = std::thread([w, b, stop] {
        std::unique_lock<std::mutex> lock(w->mutex);
        while (!w->done) {
            if (const int sig = stop->load(); sig != 0) {
                b->interrupt(sig);
                return;
            }
            w->wake.wait_for(lock, std::chrono::milliseconds(50));
        }
    });
}

EvaluationPool::~EvaluationPool() {
    watcher_.reset();  // joined before the backend goes
}

int EvaluationPool::workers() const {
    return backend_->workers();
}

std::string EvaluationPool::describe() const {
    return backend_->describe();
}

std::vector<Evaluation> EvaluationPool::evaluate(const std::vector<std::vector<double>>& xs,
                                                 const EvaluationDone& on_done) {
    return backend_->evaluate(xs, on_done);
}

}  // namespace gaitlab::optimize
