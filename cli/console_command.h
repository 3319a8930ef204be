// `gaitlab` alone, `gaitlab -i FILE.lua [ARGS]` and `gaitlab console [FILE.lua [ARGS]]`: the
// interactive console (docs/console.md).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace gaitlab::scripting {
class LuaHost;
}

namespace gaitlab::cli {

struct ConsoleArgs {
    std::string file;               ///< the script to run first ("" : none)
    std::vector<std::string> args;  ///< the script's arguments
    std::string seed = "0";
    std::string record;  ///< --record DIR
    bool no_record = false;
};

/// Adds the `console` command to `app`, filling `args`.
CLI::App* add_console_command(CLI::App& app, ConsoleArgs& args);

/// Runs the console until Ctrl-D (0), SIGTERM or SIGHUP (128 + the signal); `command` is the
/// command line, kept by the recordings. Installs its own handlers for SIGINT, SIGTERM and
/// SIGHUP. `prepare` (if set) is called with the console's host before anything runs in it
/// (the command line installs gaitlab.optimize's handler there).
int run_console(const ConsoleArgs& args, const std::string& command,
                const std::function<void(scripting::LuaHost&)>& prepare = {});

}  // namespace gaitlab::cli
