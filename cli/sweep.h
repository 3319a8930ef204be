// `gaitlab sweep SPEC.lua --grid NAME=FROM:TO:STEP... [--workers N] [--seed N] [--out DIR]`:
// evaluates every point of a grid over an optimization spec's parameters
// (gaitlab/optimize/sweep.h, docs/optimization.md "Parameter sweeps") and writes its results
// folder: a table, a plot, evaluations.jsonl and the best point.
#pragma once

#include <memory>
#include <string>

#include <CLI/CLI.hpp>

namespace gaitlab::cli {

/// The `sweep` subcommand: registers itself on `app`; run() once `app` has parsed a command
/// line that chose it.
class SweepCommand {
  public:
    explicit SweepCommand(CLI::App& app);
    ~SweepCommand();
    /// True when the command line chose `gaitlab sweep`.
    bool chosen() const;
    /// Runs it; the exit status (0; 1 or 2 with one line on stderr; 128 + a signal).
    int run(const std::string& command);

  private:
    struct Args;
    std::unique_ptr<Args> a_;
    CLI::App* sub_ = nullptr;
};

}  // namespace gaitlab::cli
