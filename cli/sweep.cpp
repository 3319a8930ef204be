// `gaitlab sweep` (see sweep.h).
#include "sweep.h"

#include <atomic>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "evaluation_options.h"
#include "gaitlab/error.h"
#include "gaitlab/optimize/options.h"
#include "gaitlab/optimize/sweep.h"
#include "gaitlab/terminal.h"
#include "progress.h"
#include "ranks.h"

namespace gaitlab::cli {

struct SweepCommand::Args {
    EvaluationArgs common;
    std::vector<std::string> grid;
};

SweepCommand::SweepCommand(CLI::App& app) : a_(std::make_unique<Args>()) {
    sub_ = app.add_subcommand("sweep",
                              "Evaluate an optimization spec on a grid of parameter values: a "
                              "table, a heat map (docs/optimization.md)");
    sub_->allow_extras();
    sub_->add_option("spec", a_->common.spec,
                     "The optimization spec (SPEC.lua), as gaitlab optimize's")
        ->required()
        ->type_name("SPEC.lua");
    sub_->add_option("--grid", a_->grid,
                     "The swept parameters, each NAME=FROM:TO:STEP (FROM, FROM + STEP, ... up "
                     "to TO); the others stay at the spec's initial value or their range's "
                     "centre")
        ->required()
        ->expected(1, -1)
        ->type_name("NAME=FROM:TO:STEP");
    add_evaluation_options(*sub_, a_->common, "Seed of math.random before every evaluation");
    sub_->footer(
        "Writes DIR/sweep.csv (one column per swept parameter, fitness, error; one row per\n"
        "point), DIR/sweep.png (a line plot for one swept parameter, a heat map for two),\n"
        "DIR/evaluations.jsonl (as gaitlab optimize's), DIR/best.json and the best point as a\n"
        "simulation file, DIR/best/best.xml. A grid has at most 100000 points. A failed point\n"
        "(an error, a NaN fitness, a diverging simulation) is marked in the table and the sweep\n"
        "goes on. Under mpirun -n K, rank 0 writes the results and ranks 1 .. K-1 evaluate, each\n"
        "on --workers threads (the results are those of a run on one machine). See\n"
        "docs/optimization.md.");
}

SweepCommand::~SweepCommand() = default;

bool SweepCommand::chosen() const {
    return sub_->parsed();
}

int SweepCommand::run(const std::string& command) {
    const EvaluationArgs& a = a_->common;
    optimize::SweepOptions o;
    optimize::MpiOptions mpi_options;
    try {
        o.workers = static_cast<int>(optimize::whole_number("workers", a.workers, 1, 1024));
        o.seed = optimize::whole_number("seed", a.seed, 0, UINT64_MAX);
        mpi_options.workers = o.workers;
        mpi_options.seed = o.seed;
        mpi_options.rank_timeout = rank_timeout_option(a.rank_timeout);
    } catch (const Error& e) {
        print_message(stderr, "gaitlab: %s (see 'gaitlab sweep --help')\n", e.what());
        return 2;
    }
    o.out = a.out.empty() ? default_results_folder("sweep", a.spec) : a.out;
    o.command = command;
    // under mpirun: rank 0 sweeps, the other ranks evaluate (docs/optimization.md)
    Ranks mpi;
    optimize::Spec spec;
    if (const int status = start_ranks_and_load(a.spec, mpi_options, mpi, spec); status >= 0) {
        return status;
    }
    o.backend = mpi.backend.get();
    optimize::Grid grid;
    try {
        grid = optimize::parse_grid(spec, a_->grid);
    } catch (const Error& e) {
        print_message(stderr, "gaitlab: %s (see 'gaitlab sweep --help')\n", e.what());
        return 2;
    }
    std::string swept, sizes, fixed;
    for (const optimize::Axis& ax : grid.axes) {
        swept += (swept.empty() ? "" : ", ") + spec.parameters[ax.parameter].name;
        sizes += fmt::format("{}{}", sizes.empty() ? "" : " x ", ax.values.size());
    }
    for (std::size_t i = 0; i < spec.parameters.size(); ++i) {
        bool on_grid = false;
        for (const optimize::Axis& ax : grid.axes)
            on_grid = on_grid || ax.parameter == i;
        if (!on_grid) {
            fixed += fmt::format("{}{} = {}", fixed.empty() ? "" : ", ", spec.parameters[i].name,
                                 fitness_text(grid.base[i]));
        }
    }
    const std::string shape =
        grid.axes.size() == 1
            ? fmt::format("{} at {} values", swept, grid.points())
            : fmt::format("{} on a {} grid ({} points)", swept, sizes, grid.points());
    const std::string workers = workers_text(mpi, o.workers);
    print_message(stdout, "sweep %s: %s%s, fitness %s, %s, results in %s\n", a.spec.c_str(),
                  shape.c_str(), fixed.empty() ? "" : (", " + fixed).c_str(), spec.fitness.c_str(),
                  workers.c_str(), o.out.c_str());
    std::fflush(stdout);
    ProgressLine bar;
    const auto show = [&](const optimize::SweepTick& t) {
        const double rate = t.wall > 0 ? static_cast<double>(t.done) / t.wall : 0;
        std::string line = fmt::format("sweep: {}/{} evaluated, best {}, {:.2g} per s", t.done,
                                       t.points, fitness_text(t.best), rate);
        if (rate > 0 && t.points > t.done) {
            line += fmt::format(", about {} left",
                                duration_text(static_cast<double>(t.points - t.done) / rate));
        }
        bar.show(line, t.done == t.points);
    };
    optimize::SweepResult r;
    try {
        r = optimize::run_sweep(spec, grid, o, &evaluations_stop(),
                                bar.shown_on_a_terminal()
                                    ? std::function<void(const optimize::SweepTick&)>(show)
                                    : nullptr);
        bar.clear();
    } catch (const Error& e) {
        bar.clear();
        if (const int sig = evaluations_stop().load(); sig != 0) {
            print_message(stderr, "gaitlab: interrupted; the evaluations so far are in %s\n",
                          o.out.c_str());
            return 128 + sig;
        }
        report_line(e.what());
        return 1;
    }
    if (r.failed > 0) {
        print_message(stdout, "%zu of %zu points failed (the first: %s)\n", r.failed, r.points,
                      r.first_error.c_str());
    }
    if (r.best.empty()) {
        std::fflush(stdout);
        print_message(stderr, "gaitlab: every point failed (see %s)\n", r.table.c_str());
        return 1;
    }
    const std::string best = point_text(spec, r.best);
    print_message(stdout, "best %s %s at point %zu of %zu: %s\n", spec.fitness.c_str(),
                  fitness_text(r.best_fitness).c_str(), r.best_point + 1, r.points, best.c_str());
    print_message(stdout, "results: %s, %s/evaluations.jsonl, %s/best.json\n", r.table.c_str(),
                  o.out.c_str(), o.out.c_str());
    if (!r.plot.empty()) {
        print_message(stdout, "plot: %s\n", r.plot.c_str());
    } else {
        print_message(stdout, "no plot: %s\n", r.plot_error.c_str());
    }
    print_best_simulation(r.simulation, r.simulation_error);
    return 0;
}

}  // namespace gaitlab::cli
