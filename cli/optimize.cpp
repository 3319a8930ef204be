// `gaitlab optimize` (see optimize.h).
#include "optimize.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include <fmt/format.h>

#include "evaluation_options.h"
#include "gaitlab/error.h"
#include "gaitlab/optimize/mpi.h"
#include "gaitlab/optimize/options.h"
#include "gaitlab/optimize/runner.h"
#include "gaitlab/terminal.h"
#include "progress.h"
#include "ranks.h"
#include "shell_word.h"

namespace gaitlab::cli {

namespace {

// the progress line after an evaluation: "generation 2/10: 5/8 evaluated, best 0.105722, mean
// 0.0389433, 1.6 per s, about 45 s left"
std::string tick_line(const optimize::Tick& t) {
    const double rate = t.wall > 0 ? static_cast<double>(t.evaluations) / t.wall : 0;
    const std::int64_t total = static_cast<std::int64_t>(t.generations) * t.individuals;
    std::string line = fmt::format(
        "generation {}/{}: {}/{} evaluated, best {}, mean {}, {:.2g} per s", t.generation + 1,
        t.generations, t.done, t.individuals, fitness_text(t.best), fitness_text(t.mean), rate);
    if (rate > 0 && total > t.evaluations) {
        line += fmt::format(", about {} left",
                            duration_text(static_cast<double>(total - t.evaluations) / rate));
    }
    return line;
}

// the default results folder of gaitlab.optimize{}: a script may run several optimizations
// within a second, so a taken name gets -2, -3 ... as run folders do
std::string new_results_folder(const std::string& spec) {
    const std::string base = default_results_folder("optimize", spec);
    std::string out = base;
    std::error_code ec;
    for (int n = 2; std::filesystem::exists(out, ec); ++n)
        out = fmt::format("{}-{}", base, n);
    return out;
}

}  // namespace

struct OptimizeCommand::Args {
    EvaluationArgs common;
    // --method, --generations, --population and --resume; with common's --workers, --seed and
    // --out checked by optimize::check_options, as gaitlab.optimize{}'s are
    optimize::GivenOptions given;
};

OptimizeCommand::OptimizeCommand(CLI::App& app) : a_(std::make_unique<Args>()) {
    sub_ = app.add_subcommand("optimize",
                              "Tune parameters with GA, CMA-ES or PGPE: each evaluation builds "
                              "and runs a simulation (docs/optimization.md)");
    sub_->allow_extras();
    sub_->add_option("spec", a_->common.spec, "The optimization spec (SPEC.lua)")
        ->required()
        ->type_name("SPEC.lua");
    sub_->add_option("--method", a_->given.method,
                     "ga, cmaes or pgpe (default: the spec's, or cmaes)")
        ->type_name("M");
    sub_->add_option("--generations", a_->given.generations,
                     "Generations to run (default: the spec's, or 20)")
        ->type_name("N");
    sub_->add_option("--population", a_->given.population,
                     "Individuals per generation (default: the spec's, or the method's)")
        ->type_name("N");
    add_evaluation_options(*sub_, a_->common, "Seed of the method's random stream");
    sub_->add_flag("--resume", a_->given.resume,
                   "Continue the interrupted run in --out DIR (the same spec and options; "
                   "--workers may differ)");
    sub_->footer(
        "Writes DIR/evaluations.jsonl (one line per evaluation: generation, individual,\n"
        "parameters, fitness, seconds, worker, error), DIR/best.json and the best as a\n"
        "simulation file, DIR/best/best.xml, its run recorded in DIR/run, a convergence plot\n"
        "DIR/convergence.png and the state to --resume from, DIR/state.json. A failed\n"
        "evaluation (an error, a NaN fitness, a diverging simulation) ranks last and the run\n"
        "goes on. Under mpirun -n K, rank 0 runs the method and ranks 1 .. K-1 evaluate, each\n"
        "on --workers threads. See docs/optimization.md.");
}

OptimizeCommand::~OptimizeCommand() = default;

bool OptimizeCommand::chosen() const {
    return sub_->parsed();
}

int OptimizeCommand::run(const std::string& command) {
    const EvaluationArgs& a = a_->common;
    optimize::GivenOptions given = a_->given;
    given.workers = a.workers;
    given.seed = a.seed;
    given.out = a.out;
    optimize::RunOptions o;
    optimize::MpiOptions mpi_options;
    optimize::Spec spec;
    try {
        o = optimize::check_options(given, optimize::OptionGiver::command_line);
        mpi_options.workers = o.workers;
        mpi_options.rank_timeout = rank_timeout_option(a.rank_timeout);
    } catch (const Error& e) {
        print_message(stderr, "gaitlab: %s (see 'gaitlab optimize --help')\n", e.what());
        return 2;
    }
    o.out = o.out.empty() ? default_results_folder("optimize", a.spec) : o.out;
    o.command = command;
    // under mpirun: rank 0 runs the method, the other ranks evaluate (docs/optimization.md)
    Ranks mpi;
    if (const int status = start_ranks_and_load(a.spec, mpi_options, mpi, spec); status >= 0) {
        return status;
    }
    o.backend = mpi.backend.get();
    std::string names;
    for (const auto& p : spec.parameters)
        names += (names.empty() ? "" : ", ") + p.name;
    const std::string workers = workers_text(mpi, o.workers);
    print_message(stdout, "optimize %s: %zu parameter%s (%s), fitness %s, %s, results in %s\n",
                  a.spec.c_str(), spec.parameters.size(), spec.parameters.size() == 1 ? "" : "s",
                  names.c_str(), spec.fitness.c_str(), workers.c_str(), o.out.c_str());
    std::fflush(stdout);
    // on a terminal, a line on stderr rewritten after each evaluation; taken away before the
    // generation's summary line and at the end
    ProgressLine bar;
    const auto clear_bar = [&] { bar.clear(); };
    const auto show_bar = [&](const optimize::Tick& t) {
        bar.show(tick_line(t), t.done >= t.individuals);
    };
    optimize::RunResult r;
    try {
        r = optimize::run_optimization(
            spec, o,
            [&](const optimize::Progress& p) {
                const double rate = p.wall > 0 ? static_cast<double>(p.evaluations) / p.wall : 0;
                const double left =
                    p.generation + 1 < p.generations && p.generation >= 0
                        ? p.wall / (p.generation + 1) * (p.generations - p.generation - 1)
                        : 0;
                std::string line = fmt::format(
                    "generation {}/{}: best {}, mean {}, {} evaluations, {:.2g} per s, {} left",
                    p.generation + 1, p.generations, fitness_text(p.best), fitness_text(p.mean),
                    p.evaluations, rate, duration_text(left));
                if (p.failed > 0) {
                    line += fmt::format(" ({} failed: {})", p.failed, p.first_error);
                }
                clear_bar();
                print_message(stdout, "%s\n", line.c_str());
                std::fflush(stdout);
            },
            &evaluations_stop(),
            bar.shown_on_a_terminal() ? std::function<void(const optimize::Tick&)>(show_bar)
                                      : nullptr);
        clear_bar();
    } catch (const Error& e) {
        clear_bar();
        if (const int sig = evaluations_stop().load(); sig != 0) {
            print_message(stderr,
                          "gaitlab: interrupted; the evaluations so far are in %s (go on with "
                          "--resume --out %s)\n",
                          o.out.c_str(), o.out.c_str());
            return 128 + sig;
        }
        report_line(e.what());
        return 1;
    }
    if (r.best.empty()) {
        print_message(stderr, "gaitlab: every evaluation failed (see %s/evaluations.jsonl)\n",
                      o.out.c_str());
        return 1;
    }
    const std::string best = point_text(spec, r.best);
    print_message(stdout, "best %s %s after %lld evaluations (%s, seed %llu): %s\n",
                  spec.fitness.c_str(), fitness_text(r.best_fitness).c_str(),
                  static_cast<long long>(r.evaluations), r.method.c_str(),
                  static_cast<unsigned long long>(o.seed), best.c_str());
    print_message(stdout, "results: %s/evaluations.jsonl, %s/best.json\n", o.out.c_str(),
                  o.out.c_str());
    print_best_simulation(r.simulation, r.simulation_error);
    if (!r.run.empty()) {
        print_message(stdout, "the best's run recorded: gaitlab view %s, gaitlab data %s --list\n",
                      shell_word(r.run).c_str(), shell_word(r.run).c_str());
    } else if (!r.run_error.empty()) {
        print_message(stdout, "the best's run could not be recorded: %s\n", r.run_error.c_str());
    }
    if (!r.plot.empty()) {
        print_message(stdout, "convergence plot: %s\n", r.plot.c_str());
    } else {
        print_message(stdout, "the convergence plot could not be drawn: %s\n",
                      r.plot_error.c_str());
    }
    return 0;
}

scripting::LuaHost::OptimizeHandler lua_optimize_handler() {
    return [](const scripting::LuaHost::OptimizeRequest& request) {
        optimize::GivenOptions given;
        given.method = request.method;
        given.generations = request.generations;
        given.population = request.population;
        given.workers = request.workers;
        given.seed = request.seed;
        given.out = request.out;
        given.resume = request.resume;
        optimize::RunOptions o;
        try {
            o = optimize::check_options(given, optimize::OptionGiver::lua);
        } catch (const optimize::OptionError& e) {
            throw scripting::FieldError(e.option(), e.problem());
        }
        if (o.out.empty()) o.out = new_results_folder(request.spec);
        o.command = fmt::format("gaitlab.optimize{{ spec = \"{}\" }}", request.spec);
        const optimize::Spec spec = optimize::load_spec(request.spec);
        // on a terminal, one line on stderr rewritten after each evaluation, gone at the end
        ProgressLine bar;
        optimize::RunResult r;
        try {
            r = optimize::run_optimization(
                spec, o, {}, request.stop,
                bar.shown_on_a_terminal()
                    ? std::function<void(const optimize::Tick&)>([&bar](const optimize::Tick& t) {
                          bar.show(tick_line(t), t.done >= t.individuals);
                      })
                    : nullptr);
        } catch (const Error& e) {
            bar.clear();
            if (request.stop && request.stop->load() != 0) {
                // the host's interrupt stops the script with its own message ("interrupted
                // (SIGINT)"): where the evaluations went is said here
                print_message(stderr,
                              "gaitlab: optimization interrupted: the evaluations so far are in "
                              "%s (go on with gaitlab.optimize{ ..., out = \"%s\", resume = true "
                              "})\n",
                              o.out.c_str(), o.out.c_str());
                std::fflush(stderr);
                throw Error("gaitlab.optimize: interrupted");
            }
            throw;
        }
        bar.clear();
        if (r.best.empty()) {
            throw Error(fmt::format(
                "gaitlab.optimize: every evaluation failed (see {}/evaluations.jsonl)", o.out));
        }
        scripting::LuaHost::OptimizeResult result;
        for (size_t i = 0; i < r.best.size(); ++i) {
            result.parameters.push_back(
                {spec.parameters[i].name, r.best[i], spec.parameters[i].integer});
        }
        result.fitness = r.best_fitness;
        result.evaluations = r.evaluations;
        result.method = r.method;
        result.generations = r.generations;
        result.population = r.population;
        // absolute: the script's own functions take relative paths from its folder, not the
        // current one (gaitlab.simulation.load(r.simulation) must find the file)
        const auto absolute = [](const std::string& path) {
            return path.empty() ? path
                                : std::filesystem::absolute(path).lexically_normal().string();
        };
        result.folder = absolute(o.out);
        result.simulation = absolute(r.simulation);
        result.run = absolute(r.run);
        result.plot = absolute(r.plot);
        return result;
    };
}

}  // namespace gaitlab::cli
