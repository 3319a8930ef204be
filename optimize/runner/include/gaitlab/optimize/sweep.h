// Parameter sweeps: `gaitlab sweep SPEC.lua --grid NAME=FROM:TO:STEP ...` evaluates every point
// of a grid over some of an optimization spec's parameters (the others at the spec's `initial`
// or the centre of their range) with the runner's machinery (EvaluationPool: one Lua state per
// worker, results in grid order), and writes a table, a plot and the best point
// (docs/optimization.md, "Parameter sweeps").
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "gaitlab/optimize/runner.h"

namespace gaitlab::optimize {

/// The most points a grid may have: 100 000 (at 1 s per evaluation, 14 hours on 2 workers).
inline constexpr std::size_t kMaxGridPoints = 100000;

/// One swept parameter.
struct Axis {
    std::size_t parameter = 0;   ///< index in Spec::parameters
    std::vector<double> values;  ///< FROM, FROM + STEP, ... up to TO, in parameter units
};

/// A grid: the axes in the order given; the first varies slowest.
struct Grid {
    std::vector<Axis> axes;
    std::vector<double> base;  ///< every parameter's value off the grid (spec order)
    std::size_t points() const;
    /// Point `i` (0 <= i < points()) in parameter units, spec order.
    std::vector<double> point(std::size_t i) const;
};

/// Reads `--grid` arguments, each NAME=FROM:TO:STEP, for `spec`. Throws SpecError naming the
/// argument and what is expected: bad syntax, an unknown parameter or one given twice, a step
/// that is not > 0, an empty or inverted range, values outside the parameter's range in the
/// spec, a non-whole FROM or STEP for an integer parameter, more than kMaxGridPoints points.
Grid parse_grid(const Spec& spec, const std::vector<std::string>& args);

/// How run_sweep runs.
struct SweepOptions {
    int workers = 1;         ///< >= 1
    std::uint64_t seed = 0;  ///< seeds math.random before every evaluation
    std::string out;         ///< the results folder: created; must not exist or be empty
    std::string command;     ///< the command line, kept in best.json
    /// Who evaluates (not owned; MPI ranks): nullptr for `workers` threads in this process.
    EvaluationBackend* backend = nullptr;
};

/// After each evaluation (from the worker that ran it, one call at a time).
struct SweepTick {
    std::size_t done = 0;    ///< points evaluated so far
    std::size_t points = 0;  ///< points in the grid
    double best = 0;         ///< best fitness so far (NaN: none yet)
    double wall = 0;         ///< wall seconds since the sweep began
};

/// The outcome of a sweep.
struct SweepResult {
    std::vector<double> best;  ///< the best point, parameter units (empty: every point failed)
    double best_fitness = 0;   ///< NaN when every point failed
    std::size_t best_point = 0;
    std::size_t points = 0;
    std::size_t failed = 0;
    std::string first_error;       ///< the message of the first failed point
    std::string table;             ///< OUT/sweep.csv
    std::string plot;              ///< OUT/sweep.png; "" when there is none
    std::string plot_error;        ///< why not (3 or more axes, every point failed, gnuplot)
    std::string simulation;        ///< OUT/best/best.xml; "" when it could not be saved
    std::string simulation_error;  ///< why not
};

/// Evaluates every point of `grid` on options.workers threads, writing OUT/evaluations.jsonl as
/// it goes (in grid order, "generation" 0, "individual" the point's number), then OUT/sweep.csv
/// (one column per axis, fitness, error), OUT/sweep.png (a line plot for one axis, a heat map
/// for two; its gnuplot script and data next to it), OUT/best.json and OUT/best/best.xml. The
/// best is the point with the highest fitness, the first in grid order among equals. Stops with
/// Error ("interrupted") when `stop` becomes non-zero. Throws SpecError for bad options, IoError
/// when OUT cannot be written.
SweepResult run_sweep(const Spec& spec, const Grid& grid, const SweepOptions& options,
                      const std::atomic<int>* stop = nullptr,
                      const std::function<void(const SweepTick&)>& on_evaluation = {});

}  // namespace gaitlab::optimize
