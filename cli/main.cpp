// The gaitlab executable: gaitlab run FILE.lua|FILE.xml, gaitlab FILE.lua, --help, --version.
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/version.h"

namespace {

bool ends_with(const std::string& s, const char* suffix) {
    const std::string x(suffix);
    return s.size() >= x.size() && s.compare(s.size() - x.size(), x.size(), x) == 0;
}

int run_script(const std::string& file, std::uint64_t seed, const std::vector<std::string>& args) {
    const bool xml = ends_with(file, ".xml");
    if (!ends_with(file, ".lua") && !xml) {
        std::fprintf(stderr,
                     "gaitlab: %s: expected a Lua script (FILE.lua) or a simulation file "
                     "(FILE.xml)\n",
                     file.c_str());
        return 2;
    }
    try {
        gaitlab::scripting::LuaHost host;
        // failed reloads of controller files and controllers failing under
        // on_controller_error = "continue" are reported while the script goes on
        host.set_reporter([](const std::string& message) {
            std::fprintf(stderr, "gaitlab: %s\n", message.c_str());
        });
        host.seed(seed);
        host.set_args(file, args);
        if (xml) {
            host.run_simulation_file(file);
        } else {
            host.run_file(file);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gaitlab: %s\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> argl(argv + 1, argv + argc);
    // "gaitlab FILE.lua ..." is "gaitlab run FILE.lua ..." (and FILE.xml)
    if (!argl.empty() && (ends_with(argl[0], ".lua") || ends_with(argl[0], ".xml"))) {
        argl.insert(argl.begin(), "run");
    }

    CLI::App app{"gaitlab: simulate modular robots and their locomotion controllers", "gaitlab"};
    app.set_version_flag("--version", std::string("gaitlab ") + gaitlab::version());
    app.require_subcommand(0, 1);

    std::string file;
    std::uint64_t seed = 0;
    CLI::App* run = app.add_subcommand("run", "Run a Lua script, or a simulation file, headless");
    run->add_option("file", file, "The script (FILE.lua) or simulation file (FILE.xml)")
        ->required();
    run->add_option("--seed", seed, "Seed for everything random (math.random too)")
        ->capture_default_str();
    // from the first argument after FILE that gaitlab does not know, everything goes to the
    // script, in order (CLI11 leaves it in remaining())
    run->prefix_command();
    run->footer("Arguments after FILE go to the script as arg[1], arg[2], ...");

    std::vector<const char*> args{argv[0]};
    for (const std::string& a : argl)
        args.push_back(a.c_str());
    try {
        app.parse(static_cast<int>(args.size()), args.data());
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // a failure is one line on stderr, like every other failure of gaitlab
        std::fprintf(stderr, "gaitlab: %s (see 'gaitlab --help')\n", e.what());
        return e.get_exit_code();
    }
    if (*run) return run_script(file, seed, run->remaining());

    std::fputs(app.help().c_str(), stdout);
    std::fputs(
        "\nThe interactive console is not part of this version yet: run a script with\n"
        "'gaitlab run FILE.lua'.\n",
        stdout);
    return argl.empty() ? 2 : 0;
}
