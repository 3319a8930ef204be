// The MPI backend (see gaitlab/optimize/mpi.h). Rank 0 hands out individuals one message each
// and keeps, per rank, the individuals it has in hand; every other rank evaluates them on its
// own threads (WorkerStates) while its main thread, the only one that calls MPI, receives
// tasks, sends results and says every second that it is alive. Nothing blocks inside MPI: each
// side polls (MPI_Iprobe) and sleeps, since a blocking receive of OpenMPI spins a core that the
// evaluations need.
//
// Messages (a communicator of their own, errors returned rather than aborting):
//   hello   rank r -> 0   int32 threads (0: the spec did not load) + the message
//   task    0 -> rank r   doubles: batch, individual, x...
//   result  rank r -> 0   u64 batch, u64 individual, f64 fitness, f64 seconds, i32 worker, error
//   alive   rank r -> 0   nothing
//   stop    0 -> rank r   nothing
#include <mpi.h>

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <limits>
#include <mutex>
#include <thread>

#include "gaitlab/error.h"
#include "gaitlab/optimize/mpi.h"
#include "gaitlab/optimize/runner.h"
#include "worker_state.h"

namespace gaitlab::optimize {

namespace {

enum Tag : int { kHello = 1, kTask = 2, kResult = 3, kAlive = 4, kStop = 5 };

constexpr auto kPoll = std::chrono::microseconds(500);
constexpr double kAliveEvery = 1.0;  // seconds between two "alive" of an evaluating rank

MPI_Comm g_comm = MPI_COMM_NULL;
// a rank was given up: MPI_Finalize would wait for it for ever (measured with OpenMPI 4.1: it
// spins in its closing fence), so the session ends with MPI_Abort instead
bool g_rank_lost = false;

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

void check(int code, const char* what) {
    if (code == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw Error(fmt::format("MPI: {}: {}", what, std::string(text, static_cast<size_t>(length))));
}

void send_bytes(const std::string& bytes, int to, int tag) {
    check(MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, to, tag, g_comm),
          "send");
}

// receives the message `status` announced (bytes)
std::string receive_bytes(const MPI_Status& status) {
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    std::string bytes(static_cast<size_t>(std::max(count, 0)), '\0');
    MPI_Status s;
    check(MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, g_comm, &s),
          "receive");
    return bytes;
}

template <class T>
void put(std::string& out, T v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <class T>
T take(const std::string& in, size_t& at) {
    T v{};
    if (at + sizeof v > in.size()) throw Error("MPI: a truncated message");
    std::memcpy(&v, in.data() + at, sizeof v);
    at += sizeof v;
    return v;
}

// ---- rank 0 ---------------------------------------------------------------------------------

struct Peer {
    int rank = 0;
    int threads = 0;                 // 0: not (or no longer) evaluating
    double heard = 0;                // when rank 0 last heard from it (now())
    std::vector<std::size_t> taken;  // individuals of the batch under way it has in hand
    std::string lost;                // why it was given up
};

class MpiBackend : public EvaluationBackend {
  public:
    MpiBackend(MpiSession& session, const MpiOptions& options) : options_(options) {
        for (int r = 1; r < session.size(); ++r) {
            Peer p;
            p.rank = r;
            peers_.push_back(p);
        }
        // every rank says how many threads it runs, or why it could not load the spec
        const double start = now();
        std::size_t answered = 0;
        while (answered < peers_.size()) {
            MPI_Status status;
            int flag = 0;
            check(MPI_Iprobe(MPI_ANY_SOURCE, kHello, g_comm, &flag, &status), "probe");
            if (flag) {
                const std::string bytes = receive_bytes(status);
                size_t at = 0;
                Peer& p = peers_[static_cast<size_t>(status.MPI_SOURCE - 1)];
                p.threads = take<std::int32_t>(bytes, at);
                p.heard = now();
                if (p.threads <= 0) {
                    p.threads = 0;
                    p.lost = bytes.substr(at);
                }
                ++answered;
                continue;
            }
            if (now() - start > options_.rank_timeout) {
                for (Peer& p : peers_) {
                    if (p.heard == 0) {
                        p.lost =
                            fmt::format("no word within {} s of the start", options_.rank_timeout);
                    }
                }
                break;
            }
            std::this_thread::sleep_for(kPoll);
        }
        for (const Peer& p : peers_) {
            if (p.threads > 0) workers_ += p.threads;
        }
        if (workers_ == 0) {
            stop_all();
            throw Error("no MPI rank can evaluate: " + lost_list());
        }
        for (const Peer& p : peers_) {
            if (p.threads == 0 && options_.warn)
                options_.warn(fmt::format("rank {} does not evaluate: {}", p.rank, p.lost));
        }
    }

    ~MpiBackend() override { stop_all(); }

    int workers() const override { return workers_; }

    std::string describe() const override {
        const auto ranks = std::count_if(peers_.begin(), peers_.end(),
                                         [](const Peer& p) { return p.threads > 0; });
        return fmt::format("{} MPI rank{} evaluating, {} worker{} in all", ranks,
                           ranks == 1 ? "" : "s", workers_, workers_ == 1 ? "" : "s");
    }

    void interrupt(int signal) override { signal_.store(signal); }

    std::vector<Evaluation> evaluate(const std::vector<std::vector<double>>& xs,
                                     const EvaluationDone& on_done) override {
        std::vector<Evaluation> results(xs.size());
        if (xs.empty()) return results;
        ++batch_;
        std::deque<std::size_t> pending;
        for (std::size_t i = 0; i < xs.size(); ++i)
            pending.push_back(i);
        std::size_t remaining = xs.size();
        std::vector<double> task;
        while (remaining > 0) {
            if (const int sig = signal_.load(); sig != 0) {
                // what is not back yet fails; late results are of a batch gone, dropped
                for (Peer& p : peers_)
                    p.taken.clear();
                for (auto& e : results) {
                    if (e.worker < 0) {
                        e.error = fmt::format("interrupted (signal {})", sig);
                        e.fitness = std::numeric_limits<double>::quiet_NaN();
                    }
                }
                return results;
            }
            // each evaluating rank gets one individual more than it has threads: the next one
            // is there when a thread ends
            for (Peer& p : peers_) {
                while (p.threads > 0 && !pending.empty() &&
                       p.taken.size() < static_cast<std::size_t>(p.threads) + 1) {
                    const std::size_t i = pending.front();
                    pending.pop_front();
                    task.assign({static_cast<double>(batch_), static_cast<double>(i)});
                    task.insert(task.end(), xs[i].begin(), xs[i].end());
                    const int code = MPI_Send(task.data(), static_cast<int>(task.size()),
                                              MPI_DOUBLE, p.rank, kTask, g_comm);
                    if (code != MPI_SUCCESS) {
                        pending.push_front(i);
                        give_up(p, "cannot be reached", pending);
                        break;
                    }
                    p.taken.push_back(i);
                }
            }
            bool heard = false;
            for (;;) {
                MPI_Status status;
                int flag = 0;
                check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, g_comm, &flag, &status), "probe");
                if (!flag) break;
                heard = true;
                const std::string bytes = receive_bytes(status);
                if (status.MPI_SOURCE < 1 || status.MPI_SOURCE > static_cast<int>(peers_.size()))
                    continue;
                Peer& p = peers_[static_cast<size_t>(status.MPI_SOURCE - 1)];
                p.heard = now();
                if (status.MPI_TAG != kResult) continue;
                size_t at = 0;
                const auto batch = take<std::uint64_t>(bytes, at);
                const auto i = static_cast<std::size_t>(take<std::uint64_t>(bytes, at));
                Evaluation e;
                e.fitness = take<double>(bytes, at);
                e.seconds = take<double>(bytes, at);
                e.worker = take<std::int32_t>(bytes, at);
                e.error = bytes.substr(at);
                e.rank = p.rank;
                const auto it = std::find(p.taken.begin(), p.taken.end(), i);
                // a result of an earlier batch, or of a rank given up whose individual went
                // elsewhere: already done by another, dropped
                if (batch != batch_ || it == p.taken.end()) continue;
                p.taken.erase(it);
                if (!e.error.empty()) e.fitness = std::numeric_limits<double>::quiet_NaN();
                results[i] = std::move(e);
                --remaining;
                if (on_done) on_done(i, results[i]);
            }
            const double t = now();
            for (Peer& p : peers_) {
                if (p.threads > 0 && t - p.heard > options_.rank_timeout) {
                    give_up(p, fmt::format("no word for {:.3g} s", t - p.heard), pending);
                }
            }
            if (remaining > 0 && workers_ == 0) {
                throw Error(fmt::format(
                    "every evaluating MPI rank is lost ({}): {} evaluations of this generation "
                    "cannot be made",
                    lost_list(), remaining));
            }
            if (!heard) std::this_thread::sleep_for(kPoll);
        }
        return results;
    }

  private:
    void give_up(Peer& p, const std::string& why, std::deque<std::size_t>& pending) {
        p.lost = why;
        g_rank_lost = true;
        workers_ -= p.threads;
        p.threads = 0;
        // its individuals go first, in their order, to the ranks left
        std::sort(p.taken.begin(), p.taken.end());
        pending.insert(pending.begin(), p.taken.begin(), p.taken.end());
        const std::size_t n = p.taken.size();
        p.taken.clear();
        if (options_.warn) {
            options_.warn(
                fmt::format("MPI rank {} is given up ({}){}", p.rank, why,
                            n > 0 ? fmt::format(": its {} evaluation{} go to the other ranks", n,
                                                n == 1 ? "" : "s")
                                  : std::string()));
        }
    }

    std::string lost_list() const {
        std::string s;
        for (const Peer& p : peers_) {
            if (!p.lost.empty())
                s += fmt::format("{}rank {}: {}", s.empty() ? "" : "; ", p.rank, p.lost);
        }
        return s;
    }

    void stop_all() {
        if (stopped_) return;
        stopped_ = true;
        for (const Peer& p : peers_) {
            // to every rank, the given up too (a slow rank that is alive must end); errors
            // (a rank gone) are ignored
            MPI_Send(nullptr, 0, MPI_BYTE, p.rank, kStop, g_comm);
        }
    }

    MpiOptions options_;
    std::vector<Peer> peers_;
    int workers_ = 0;
    std::uint64_t batch_ = 0;
    std::atomic<int> signal_{0};
    bool stopped_ = false;
};

// ---- ranks 1 .. K-1 -------------------------------------------------------------------------

struct Task {
    std::uint64_t batch = 0;
    std::uint64_t individual = 0;
    std::vector<double> x;
};

struct Done {
    std::uint64_t batch = 0;
    std::uint64_t individual = 0;
    Evaluation e;
};

// rank 0 says stop (or a signal does): waits for it without spinning (after a spec that did
// not load)
void wait_for_stop(const std::atomic<int>* signal) {
    for (;;) {
        if (signal && signal->load() != 0) return;
        MPI_Status status;
        int flag = 0;
        if (MPI_Iprobe(0, MPI_ANY_TAG, g_comm, &flag, &status) != MPI_SUCCESS) return;
        if (flag) {
            receive_bytes(status);
            if (status.MPI_TAG == kStop) return;
            continue;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

}  // namespace

bool mpi_built() {
    return true;
}

MpiSession::MpiSession() {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (initialized) throw Error("MPI: MpiSession: MPI is already initialised (one per process)");
    int provided = 0;
    // only the main thread of each rank calls MPI
    if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        throw Error("MPI: MPI_Init_thread failed");
    MPI_Comm_dup(MPI_COMM_WORLD, &g_comm);
    // a rank gone is reported as an error code here, not as the end of the job
    MPI_Comm_set_errhandler(g_comm, MPI_ERRORS_RETURN);
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(g_comm, &rank_);
    MPI_Comm_size(g_comm, &size_);
}

MpiSession::~MpiSession() {
    if (g_rank_lost) {
        // everything is written: the results folder, the messages
        std::fflush(stdout);
        std::fflush(stderr);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Comm_free(&g_comm);
    MPI_Finalize();
}

std::unique_ptr<EvaluationBackend> make_mpi_backend(MpiSession& session,
                                                    const MpiOptions& options) {
    if (session.rank() != 0) throw Error("MPI: the backend runs on rank 0 only");
    if (session.size() < 2)
        throw Error(
            "MPI: the backend needs at least 2 ranks (rank 0 hands out, the others evaluate)");
    if (!(options.rank_timeout > 0))
        throw SpecError(fmt::format("--rank-timeout: a number of seconds > 0 expected, got {}",
                                    options.rank_timeout));
    return std::make_unique<MpiBackend>(session, options);
}

int mpi_serve(MpiSession& session, const std::string& spec_file, const MpiOptions& options,
              const std::atomic<int>* stop_signal) {
    if (session.rank() == 0) throw Error("MPI: rank 0 does not serve evaluations");
    std::unique_ptr<WorkerStates> states;
    try {
        if (options.workers < 1) {
            throw SpecError(
                fmt::format("--workers: a whole number >= 1 expected, got {}", options.workers));
        }
        const Spec spec = load_spec(spec_file);
        states = std::make_unique<WorkerStates>(spec, options.workers, options.seed);
    } catch (const std::exception& e) {
        std::string hello;
        put<std::int32_t>(hello, 0);
        hello += e.what();
        send_bytes(hello, 0, kHello);
        // rank 0 reports it and ends the run; a rank that ended with an error would make
        // mpirun end the job before rank 0 has said why
        wait_for_stop(stop_signal);
        return 0;
    }
    std::string hello;
    put<std::int32_t>(hello, options.workers);
    send_bytes(hello, 0, kHello);

    std::mutex mutex;
    std::condition_variable work_cv;  // a task, or stop
    std::condition_variable done_cv;  // a result
    std::deque<Task> tasks;
    std::vector<Done> done;
    bool stop = false;
    std::vector<std::thread> threads;
    for (int w = 0; w < options.workers; ++w) {
        threads.emplace_back([&, w] {
            std::unique_lock<std::mutex> lock(mutex);
            for (;;) {
                work_cv.wait(lock, [&] { return stop || !tasks.empty(); });
                if (stop) return;
                Task t = std::move(tasks.front());
                tasks.pop_front();
                lock.unlock();
                Done d{t.batch, t.individual, states->run(t.x, w)};
                lock.lock();
                done.push_back(std::move(d));
                done_cv.notify_one();
            }
        });
    }
    const auto join = [&](int signal) {
        {
            std::lock_guard<std::mutex> lock(mutex);
            stop = true;
        }
        // the evaluations under way end at once (their results are not wanted)
        states->interrupt(signal);
        work_cv.notify_all();
        for (std::thread& t : threads)
            t.join();
    };
    double alive = now();
    std::vector<Done> sending;
    int signal = 0;
    try {
        for (;;) {
            if (stop_signal && (signal = stop_signal->load()) != 0) break;
            bool stopping = false;
            for (;;) {
                MPI_Status status;
                int flag = 0;
                check(MPI_Iprobe(0, MPI_ANY_TAG, g_comm, &flag, &status), "probe");
                if (!flag) break;
                if (status.MPI_TAG == kStop) {
                    receive_bytes(status);
                    stopping = true;
                    break;
                }
                int count = 0;
                MPI_Get_count(&status, MPI_DOUBLE, &count);
                std::vector<double> v(static_cast<size_t>(std::max(count, 0)));
                MPI_Status s;
                check(MPI_Recv(v.data(), count, MPI_DOUBLE, 0, status.MPI_TAG, g_comm, &s),
                      "receive");
                if (status.MPI_TAG != kTask || v.size() < 2) continue;
                Task t;
                t.batch = static_cast<std::uint64_t>(v[0]);
                t.individual = static_cast<std::uint64_t>(v[1]);
                t.x.assign(v.begin() + 2, v.end());
                {
                    std::lock_guard<std::mutex> lock(mutex);
                    tasks.push_back(std::move(t));
                }
                work_cv.notify_one();
            }
            if (stopping) break;
            {
                std::unique_lock<std::mutex> lock(mutex);
                if (done.empty()) done_cv.wait_for(lock, kPoll);
                sending.swap(done);
            }
            for (const Done& d : sending) {
                std::string bytes;
                put<std::uint64_t>(bytes, d.batch);
                put<std::uint64_t>(bytes, d.individual);
                put<double>(bytes, d.e.fitness);
                put<double>(bytes, d.e.seconds);
                put<std::int32_t>(bytes, d.e.worker);
                bytes += d.e.error;
                send_bytes(bytes, 0, kResult);
            }
            if (!sending.empty()) alive = now();
            sending.clear();
            if (now() - alive >= kAliveEvery) {
                send_bytes(std::string(), 0, kAlive);
                alive = now();
            }
        }
    } catch (...) {
        join(15);
        throw;
    }
    join(signal != 0 ? signal : 15);
    return signal != 0 ? 128 + signal : 0;
}

}  // namespace gaitlab::optimize
