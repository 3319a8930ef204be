// `gaitlab edit ENV.xml [--robot FILE]... [--port P] [--host ADDR]`: the environment editor in
// a browser (docs/viewer.md, "Editing a world"), without a simulation.
#pragma once

#include <memory>

#include <CLI/CLI.hpp>

namespace gaitlab::cli {

/// The `edit` subcommand: registers itself on `app`; run() once `app` has parsed a command line
/// that chose it.
class EditCommand {
  public:
    explicit EditCommand(CLI::App& app);
    ~EditCommand();
    /// True when the command line chose `gaitlab edit`.
    bool chosen() const;
    /// Serves the editor until SIGINT, SIGTERM or SIGHUP (0), or says why it cannot (1, 2).
    int run();

  private:
    struct Args;
    std::unique_ptr<Args> a_;
};

}  // namespace gaitlab::cli
