// c_host FILE.lua|FILE.xml [ARGS...]: `gaitlab run --no-record FILE ARGS` on the C Lua core.
//
// It links Debian's C liblua5.4, where a Lua error is a longjmp, and gaitlab_scripting_c, the
// scripting objects the module gaitlab/core.so is made of, so that every error path of the
// bindings runs as it runs in lua5.4 with the module, here under the sanitizers of the asan
// preset (LeakSanitizer sees a destructor that a longjmp skipped). It prints what `gaitlab run`
// prints, so the tests compare the two byte for byte (tests/lua_module/CMakeLists.txt): the
// script's output, the reports ("gaitlab: ..."), the error ("gaitlab: MESSAGE", exit status 1)
// and a signal ("gaitlab: MESSAGE", exit status 128 + the signal).
#include <dlfcn.h>
#include <signal.h>
#include <unistd.h>

#include <lua.hpp>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "gaitlab/scripting/lua_host.h"

namespace {

std::atomic<gaitlab::scripting::LuaHost*> g_host{nullptr};
volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_signal(int sig) {
    if (g_signal != 0) _exit(128 + sig);
    g_signal = sig;
    if (gaitlab::scripting::LuaHost* host = g_host.load()) host->interrupt(sig);
}

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: c_host FILE.lua|FILE.xml [ARGS...]\n");
        return 2;
    }
    // the process must run the C core, and only it: the Lua API must come from liblua5.4.so
    Dl_info api{};
    if (!dladdr(reinterpret_cast<void*>(&lua_pcallk), &api) || !api.dli_fname ||
        std::string(api.dli_fname).find("/liblua5.4.so") == std::string::npos) {
        std::fprintf(stderr, "c_host: the Lua API does not come from the C liblua5.4 (%s)\n",
                     api.dli_fname ? api.dli_fname : "unknown");
        return 2;
    }
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE})
        sigaction(sig, &sa, nullptr);

    const std::string file = argv[1];
    const std::vector<std::string> args(argv + 2, argv + argc);
    std::string error;
    try {
        gaitlab::scripting::LuaHost host;
        host.set_reporter([](const std::string& message) {
            std::fprintf(stderr, "gaitlab: %s\n", message.c_str());
        });
        gaitlab::scripting::RecordSettings rec;
        rec.by_default = true;
        rec.disabled = true;  // --no-record
        rec.name = std::filesystem::path(file).stem().string();
        rec.script = file;
        host.set_recording(rec);
        host.seed(0);
        host.set_args(file, args);
        g_host.store(&host);
        if (g_signal != 0) host.interrupt(g_signal);
        try {
            if (ends_with(file, ".xml")) {
                host.run_simulation_file(file);
            } else {
                host.run_file(file);
            }
        } catch (const std::exception& e) {
            error = e.what();
        }
        if (const int n = host.playing(); n > 0 && error.empty()) {
            std::fprintf(stderr,
                         "note: %d simulation%s left playing when the script ended: simulations "
                         "play in the console (gaitlab -i %s)\n",
                         n, n == 1 ? " was" : "s were", file.c_str());
        }
        try {
            host.finish(error);
        } catch (const std::exception& e) {
            if (error.empty()) error = e.what();
        }
        g_host.store(nullptr);
    } catch (const std::exception& e) {
        if (error.empty()) error = e.what();
    }
    std::fflush(stdout);
    if (g_signal != 0) {
        if (g_signal != SIGPIPE) {
            std::fprintf(stderr, "gaitlab: %s\n", error.empty() ? "interrupted" : error.c_str());
        }
        return 128 + g_signal;
    }
    if (!error.empty()) {
        std::fprintf(stderr, "gaitlab: %s\n", error.c_str());
        return 1;
    }
    return 0;
}
