// The gaitlab executable: gaitlab run FILE.lua, gaitlab FILE.lua, --help, --version.
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
    if (!ends_with(file, ".lua")) {
        std::fprintf(stderr, "gaitlab: %s: expected a Lua script (FILE.lua)\n", file.c_str());
        return 2;
    }
    try {
        gaitlab::scripting::LuaHost host;
        host.seed(seed);
        host.set_args(file, args);
        host.run_file(file);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gaitlab: %s\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> argl(argv + 1, argv + argc);
    // "gaitlab FILE.lua ..." is "gaitlab run FILE.lua ..."
    if (!argl.empty() && ends_with(argl[0], ".lua")) argl.insert(argl.begin(), "run");

    CLI::App app{"gaitlab: simulate modular robots and their locomotion controllers", "gaitlab"};
    app.set_version_flag("--version", std::string("gaitlab ") + gaitlab::version());
    app.require_subcommand(0, 1);

    std::string file;
    std::uint64_t seed = 0;
    std::vector<std::string> script_args;
    CLI::App* run = app.add_subcommand("run", "Run a Lua script headless");
    run->add_option("file", file, "The script (FILE.lua)")->required();
    run->add_option("--seed", seed, "Seed for everything random (math.random too)")
        ->capture_default_str();
    run->add_option("args", script_args, "Arguments for the script: arg[1], arg[2], ...");
    run->prefix_command();  // everything after FILE goes to the script

    std::vector<std::string> reversed(argl.rbegin(), argl.rend());
    try {
        app.parse(reversed);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    if (*run) return run_script(file, seed, script_args);

    std::fputs(app.help().c_str(), stdout);
    std::fputs("\nThe interactive console is not part of this version yet: run a script with\n"
               "'gaitlab run FILE.lua'.\n",
               stdout);
    return argl.empty() ? 2 : 0;
}
