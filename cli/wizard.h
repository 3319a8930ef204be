// `gaitlab new [DIR]`: the beginner wizard. It asks for a robot, its controllers and joint
// groups, a world and the simulation options, one explained question at a time (Enter takes
// the default), writes every part into a project folder with generated names, then runs the
// simulation. Nothing is written before the last answer, and the project appears at once
// (built in a hidden folder next to it, then renamed): an interrupted wizard leaves nothing.
#pragma once

#include <memory>

#include <CLI/CLI.hpp>

namespace gaitlab::cli {

/// The `new` subcommand of the gaitlab command line: registers itself on `app`; run() once
/// `app` has parsed a command line that chose it.
class NewCommand {
  public:
    explicit NewCommand(CLI::App& app);
    ~NewCommand();
    /// True when the command line chose `gaitlab new`.
    bool chosen() const;
    /// Runs the wizard on standard input and output; the exit status (0; 1 with one line on
    /// stderr; 128 + the signal when SIGINT, SIGTERM or SIGHUP stopped it).
    int run();

  private:
    struct Args;
    std::unique_ptr<Args> a_;
};

}  // namespace gaitlab::cli
