// `gaitlab make robot|world|actuation|sim [options] -o FILE` (expert mode): each part of a
// simulation made as a file of its own, so one robot file serves several actuations and worlds.
#pragma once

#include <memory>

#include <CLI/CLI.hpp>

namespace gaitlab::cli {

/// The `make` subcommand of the gaitlab command line: registers itself (and its four
/// subcommands) on `app`; run() once `app` has parsed a command line that chose it.
class MakeCommand {
  public:
    explicit MakeCommand(CLI::App& app);
    ~MakeCommand();
    /// True when the command line chose `gaitlab make`.
    bool chosen() const;
    /// Makes the file; the exit status (0, or 1/2 with one line on stderr).
    int run();

  private:
    struct Args;
    std::unique_ptr<Args> a_;
};

}  // namespace gaitlab::cli
