// The results folder's pieces that `gaitlab optimize` and `gaitlab sweep` share: the folder
// itself (new or empty), one evaluations.jsonl line per evaluation, parameters and fitness as
// JSON, files written whole or not at all; and what an optimization writes at its end besides
// best.json: the convergence plot and the best individual's run recorded (docs/optimization.md).
// Internal to the runner library.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gaitlab/optimize/runner.h"

namespace gaitlab::optimize::detail {

/// Creates the results folder `out`; one that exists must be an empty folder (an earlier run's
/// results are never overwritten). Throws SpecError naming --out, IoError.
void open_results_folder(const std::string& out);

/// name -> value in spec order, integers as JSON integers.
nlohmann::ordered_json parameters_json(const Spec& spec, const std::vector<double>& x);

/// the number, or null when it is not finite (a failed evaluation).
nlohmann::ordered_json fitness_json(double f);

/// One line of evaluations.jsonl (with its line end): generation, individual, parameters,
/// fitness, seconds, worker and, for a failed evaluation, error.
std::string evaluation_line(const Spec& spec, int generation, std::size_t individual,
                            const std::vector<double>& x, const Evaluation& ev);

/// JSON text as the results folder holds it (indented or one line; invalid UTF-8 replaced).
std::string json_text(const nlohmann::ordered_json& j, int indent);

/// Writes `text` to `path` through a temporary file renamed over it. Throws IoError naming
/// the file and the reason ("No space left on device"); the temporary file is then removed.
void write_file(const std::string& path, const std::string& text);

/// Writes all of `text` to the file descriptor `fd`, retrying after signals; false (errno
/// saying why) if it could not.
bool write_all(int fd, const std::string& text);

/// Appends `text` to the open stream `out` of the file `path` and flushes it. Throws IoError
/// naming the file and the reason.
void append_text(std::ofstream& out, const std::filesystem::path& path, const std::string& text);

/// ": " and the reason of the failed system call (strerror of `error`), or "" for 0.
std::string reason(int error);

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
