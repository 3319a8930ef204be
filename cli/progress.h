// What `gaitlab optimize` and `gaitlab sweep` share on the command line: the signal that stops
// them, the default results folder, numbers, durations and points as the progress and result
// lines show them, and the progress line itself (on a terminal only).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "gaitlab/optimize/runner.h"

namespace gaitlab::cli {

/// The signal that stops a running `gaitlab optimize` or `gaitlab sweep` (0: none yet): their
/// evaluations are interrupted, what was written so far stays.
const std::atomic<int>& evaluations_stop();

/// Sets it to `signal` (the first one stays). Async-signal-safe: the command line's signal
/// handler calls it.
void stop_evaluations(int signal);

/// runs/KIND-SPEC-YYYYmmdd-HHMMSS (SPEC: the spec file's name without folder and extension).
std::string default_results_folder(const std::string& kind, const std::string& spec);

/// "<1 s", "42 s", "3 min 05 s", "2 h 10 min".
std::string duration_text(double seconds);

/// A fitness as the progress lines show it ("0.105722"; "none" when not finite).
std::string fitness_text(double v);

/// A point's parameters as the result lines show them: "amplitude = 40, phase = 120" (`x` in
/// the order of `spec`'s parameters).
std::string point_text(const optimize::Spec& spec, const std::vector<double>& x);

/// Prints the line that says where the best point's simulation file is ("the best as a
/// simulation file: gaitlab run FILE"), or, when `file` is "", why it could not be saved.
void print_best_simulation(const std::string& file, const std::string& error);

/// A line on stderr rewritten in place, when stderr is a terminal (nothing otherwise).
class ProgressLine {
  public:
    ProgressLine();
    ~ProgressLine();
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;
    bool shown_on_a_terminal() const { return terminal_; }
    /// Shows `line` (cut to the terminal's width), at most every 200 ms unless `now` is set.
    void show(std::string line, bool now = false);
    /// Takes the line away (before other output, and at the end).
    void clear();

  private:
    bool terminal_ = false;
    bool shown_ = false;
    std::chrono::steady_clock::time_point last_;
};

}  // namespace gaitlab::cli
