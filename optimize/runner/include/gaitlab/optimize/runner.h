// The optimization runner: an optimization spec (a Lua file) says which parameters to tune, how
// to build a simulation from them and what to measure; run_optimization() evaluates each
// individual by building and running that simulation in a Lua state of its worker's own, and
// writes the results folder (docs/optimization.md, "Running an optimization"). It sits above
// gaitlab::scripting and gaitlab::optimize; the methods themselves know nothing of Lua.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "gaitlab/optimize/method.h"
#include "gaitlab/optimize/parameters.h"
#include "gaitlab/optimize/workers.h"

namespace gaitlab::scripting {
class LuaHost;
}

namespace gaitlab::optimize {

class EvaluationBackend;

/// What a spec file holds, checked (see load_spec). Parameters are sorted by name.
struct Spec {
    std::string file;                   ///< the spec file, as given
    std::vector<Parameter> parameters;  ///< sorted by name
    std::vector<double> initial;        ///< parameter units, one per parameter; empty: none given
    /// "distance", "speed", "cost_of_transport", "heading", "direction" or "function" (a Lua
    /// function)
    std::string fitness;
    std::vector<double> direction;  ///< fitness "direction": the unit vector {x, y}
    /// runs averaged per evaluation: `worlds` (how many; 0: none given) times `seeds` (empty:
    /// none given, one run with seed 0)
    int worlds = 0;
    std::vector<std::uint64_t> seeds;
    std::string robot;             ///< the robot the built-in fitness measures; "": the only one
    double duration = 0;           ///< measured simulated seconds, > 0
    double settle = 0;             ///< simulated seconds run before measuring, >= 0
    std::string method = "cmaes";  ///< default method: "ga", "cmaes" or "pgpe"
    int population = 0;            ///< default population; 0: the method's own default
    int generations = 20;          ///< default number of generations, >= 1
};

/// Loads and checks a spec file in a Lua state of its own. Throws SpecError "FILE: FIELD: what
/// is wrong (expected ...)" for a bad field, ScriptError for a file that does not load or run.
Spec load_spec(const std::string& path);

/// Evaluates individuals of a spec: a Lua state that loaded the spec file. One per worker; not
/// thread-safe itself.
class Evaluator {
  public:
    /// `seed` seeds math.random before every evaluation (gaitlab optimize: 0).
    explicit Evaluator(const Spec& spec, std::uint64_t seed = 0);
    ~Evaluator();
    Evaluator(const Evaluator&) = delete;
    Evaluator& operator=(const Evaluator&) = delete;

    /// Builds the simulation for `x` (parameter units, in spec order), runs settle + duration
    /// and returns the fitness. Throws Error naming the spec file when build or the fitness
    /// function fails, the simulation fails, or the fitness is not a finite number. The result
    /// depends on `x` only (math.random is seeded the same way before every evaluation).
    double evaluate(const std::vector<double>& x);

    /// Builds the simulation for `x` and writes it as a simulation file `path` (absolute) with
    /// its parts next to it (robot, actuation, environment: sim:save), for settle + duration
    /// seconds: `gaitlab run PATH` runs it. Throws Error naming the spec file, or the file that
    /// could not be written.
    void save(const std::vector<double>& x, const std::string& path);

    /// Stops the evaluation under way (and every later one) as the signal would: the call
    /// throws. Async-signal-safe.
    void interrupt(int signal);

  private:
    // one run: build(p, the spec's worlds[world] (nil for 0), seed) with math.random seeded
    double evaluate_case(const std::vector<double>& x, int world, std::uint64_t seed);

    Spec spec_;
    std::unique_ptr<scripting::LuaHost> host_;
    int spec_ref_ = 0;     // registry reference of the spec table
    int measure_ref_ = 0;  // registry reference of the measuring function
    std::uint64_t seed_ = 0;
};

/// Evaluates lists of parameter sets of a spec: on `workers` threads, each with its own
/// Evaluator (Lua state), or on a given backend (MPI ranks, gaitlab/optimize/backend.h). What
/// run_optimization does with each generation and run_sweep with a grid. Result i is for xs[i]
/// whatever the number of workers or the order they finish in.
class EvaluationPool {
  public:
    /// `seed` seeds math.random before every evaluation (thread workers). When `stop` becomes
    /// non-zero (a signal's number), the evaluations under way and later ones are interrupted:
    /// they fail. With `backend` (not owned), it evaluates and `workers` and `seed` are its.
    EvaluationPool(const Spec& spec, int workers, std::uint64_t seed,
                   const std::atomic<int>* stop = nullptr, EvaluationBackend* backend = nullptr);
    ~EvaluationPool();
    EvaluationPool(const EvaluationPool&) = delete;
    EvaluationPool& operator=(const EvaluationPool&) = delete;

    int workers() const;
    /// Who evaluates, for a progress line ("2 workers", "3 MPI ranks ...").
    std::string describe() const;
    /// Evaluates every point of `xs` (parameter units, spec order); `on_done` (if set) is
    /// called after each evaluation with its individual and result, one call at a time.
    std::vector<Evaluation> evaluate(const std::vector<std::vector<double>>& xs,
                                     const EvaluationDone& on_done = {});

  private:
    std::unique_ptr<EvaluationBackend> own_;
    EvaluationBackend* backend_ = nullptr;
    struct Watcher;
    std::unique_ptr<Watcher> watcher_;
};

/// How run_optimization runs (the command line's options).
struct RunOptions {
    std::string method;   ///< "" : the spec's
    int generations = 0;  ///< 0: the spec's
    int population = 0;   ///< 0: the spec's (or the method's default)
    int workers = 1;      ///< >= 1
    std::uint64_t seed = 0;
    std::string out;      ///< the results folder: created; must not exist or be empty
    std::string command;  ///< the command line, kept in best.json
    /// evaluates the generations (MPI ranks: gaitlab/optimize/mpi.h); null: `workers` threads
    /// in this process
    EvaluationBackend* backend = nullptr;
    /// Continue the run in `out` (OUT/state.json) with the same spec and options: ends as the
    /// uninterrupted run would have.
    bool resume = false;
};

/// After each generation.
struct Progress {
    int generation = 0;            ///< the generation just done, from 0
    int generations = 0;           ///< how many the run makes
    double best = 0;               ///< best fitness so far (NaN: none yet)
    double mean = 0;               ///< mean fitness of this generation's successful individuals
    int failed = 0;                ///< failed individuals in this generation
    int individuals = 0;           ///< individuals evaluated in this generation
    std::int64_t evaluations = 0;  ///< evaluated so far
    double wall = 0;               ///< wall seconds since the run began
    std::string first_error;       ///< the message of the first failed individual of the generation
};

/// After each evaluation (from the worker that ran it, one call at a time).
struct Tick {
    int generation = 0;            ///< the generation under way, from 0
    int generations = 0;           ///< how many the run makes
    int done = 0;                  ///< individuals of this generation evaluated so far
    int individuals = 0;           ///< individuals in this generation
    std::int64_t evaluations = 0;  ///< evaluated so far in the run
    double best = 0;               ///< best fitness of the generations told (NaN: none yet)
    double mean = 0;  ///< mean fitness of the last generation told (NaN: none yet, or all failed)
    double wall = 0;  ///< wall seconds since the run began
};

/// The outcome of a run.
struct RunResult {
    std::vector<double> best;  ///< parameter units (empty: every individual failed)
    double best_fitness = 0;   ///< NaN when every individual failed
    std::int64_t evaluations = 0;
    std::string method;
    int generations = 0;
    int population = 0;
    std::string simulation;        ///< OUT/best/best.xml; "" when it could not be saved
    std::string simulation_error;  ///< why not
    std::string plot;              ///< OUT/convergence.png; "" when it could not be drawn
    std::string plot_error;        ///< why not
    std::string run;               ///< OUT/run, the best individual's run recorded; "": none
    std::string run_error;         ///< why not
};

/// Runs the optimization a spec describes: the method, one Evaluator per worker, writing
/// OUT/evaluations.jsonl as generations end, and at the end OUT/best.json and the best
/// individual's simulation, OUT/best/best.xml and its parts (when it can be saved: best.json
/// says why not). Stops with Error
/// ("interrupted (SIGINT)") when `stop` becomes non-zero (checked between evaluations; pass
/// the signal's number). Throws SpecError for bad options, IoError when OUT cannot be written.
RunResult run_optimization(const Spec& spec, const RunOptions& options,
                           const std::function<void(const Progress&)>& on_generation = {},
                           const std::atomic<int>* stop = nullptr,
                           const std::function<void(const Tick&)>& on_evaluation = {});

}  // namespace gaitlab::optimize
