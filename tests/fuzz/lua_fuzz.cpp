// libFuzzer target: the Lua API. An input is a hand-written script (it starts with "--") or the
// choices from which harness/script_gen.cpp generates one: calls of the public gaitlab API with
// hostile arguments, in odd orders. Each runs in a fresh LuaHost, bounded in memory, ticks and
// wall time, in a folder of its own (harness/runner.h). A Lua error is the expected outcome of
// most inputs; a crash, sanitizer report, leak, abort, uncaught exception or timeout is a
// finding, and so are the harness's own checks (a shell command run, a write outside the
// folder, a saved file that does not load). tools/fuzz.sh builds and runs it; set
// GAITLAB_FUZZ_PRINT=1 to see each script on stderr, GAITLAB_FUZZ_SECONDS to change the wall
// time after which a script is interrupted (a finding may depend on where that happens).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "confine.h"
#include "runner.h"
#include "script_gen.h"

// libFuzzer writes crash reports and corpus entries while a script runs (when it crashes) and
// from the folder it was started in: those places stay writable under the confinement
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
    namespace fs = std::filesystem;
    gaitlab::fuzz::allow_writes_in(fs::current_path().string());
    for (int i = 1; i < *argc; ++i) {
        const std::string arg = (*argv)[i];
        std::string path;
        if (arg.rfind("-artifact_prefix=", 0) == 0 || arg.rfind("-exact_artifact_path=", 0) == 0) {
            path = arg.substr(arg.find('=') + 1);
        } else if (!arg.empty() && arg[0] != '-') {
            path = arg;  // a corpus folder or an input
        }
        if (path.empty()) continue;
        const fs::path p = fs::absolute(path);
        gaitlab::fuzz::allow_writes_in(fs::is_directory(p) ? p.string() : p.parent_path().string());
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static gaitlab::fuzz::Runner runner(GAITLAB_FUZZ_FIXTURES);
    static const bool print = std::getenv("GAITLAB_FUZZ_PRINT") != nullptr;
    static const gaitlab::fuzz::Limits limits = [] {
        gaitlab::fuzz::Limits l;
        if (const char* s = std::getenv("GAITLAB_FUZZ_SECONDS")) l.seconds = std::atof(s);
        return l;
    }();
    const gaitlab::fuzz::Script script = gaitlab::fuzz::script_for_input(data, size);
    if (print) std::fprintf(stderr, "---- lua_fuzz script\n%s\n----\n", script.code.c_str());
    runner.run(script, limits);
    return 0;
}
