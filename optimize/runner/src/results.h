// The parts of an optimization's results folder written at its end besides best.json: the
// convergence plot and the best individual's run recorded (docs/optimization.md).
#pragma once

#include <filesystem>
#include <string>

namespace gaitlab::optimize::detail {

/// OUT/convergence.png (with convergence.gp and convergence.csv): generation against the best
/// fitness so far and the generation's mean, read from OUT/evaluations.jsonl. Returns "" or
/// what went wrong (gnuplot missing ...).
std::string plot_convergence(const std::filesystem::path& out, const std::string& title,
                             const std::string& fitness);

/// Runs the simulation file `simulation` recorded into the run folder `dir` (replaced if it
/// exists), as `gaitlab run SIMULATION --record DIR` does. Returns "" or what went wrong.
std::string record_run(const std::string& simulation, const std::filesystem::path& dir,
                       const std::string& command);

}  // namespace gaitlab::optimize::detail
