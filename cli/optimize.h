// `gaitlab optimize SPEC.lua [--method ga|cmaes|pgpe] [--generations N] [--population N]
// [--workers N] [--seed N] [--out DIR]`: runs the optimization an optimization spec describes
// (gaitlab/optimize/runner.h, docs/optimization.md) and writes its results folder; and the same
// run for gaitlab.optimize{...} in the command line's Lua hosts.
#pragma once

#include <memory>

#include <CLI/CLI.hpp>

#include "gaitlab/scripting/lua_host.h"

namespace gaitlab::cli {

/// The `optimize` subcommand: registers itself on `app`; run() once `app` has parsed a command
/// line that chose it.
class OptimizeCommand {
  public:
    explicit OptimizeCommand(CLI::App& app);
    ~OptimizeCommand();
    /// True when the command line chose `gaitlab optimize`.
    bool chosen() const;
    /// Runs it; the exit status (0; 1 or 2 with one line on stderr; 128 + a signal).
    int run(const std::string& command);

  private:
    struct Args;
    std::unique_ptr<Args> a_;
    CLI::App* sub_ = nullptr;
};

/// What gaitlab.optimize{...} runs in the command line's hosts (`gaitlab run`, the console): the
/// optimization, its options checked as `gaitlab optimize` checks its own, on threads of this
/// process, stopped by the host's interrupt; a progress line on stderr when it is a terminal.
scripting::LuaHost::OptimizeHandler lua_optimize_handler();

}  // namespace gaitlab::cli
