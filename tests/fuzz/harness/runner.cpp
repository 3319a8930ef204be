#include "runner.h"

#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <lua.hpp>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <thread>
#include <vector>

#include "confine.h"
#include "gaitlab/error.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/simulation.h"

namespace gaitlab::fuzz {

namespace fs = std::filesystem;

namespace {

// what every fuzzed script runs under, besides the confinement of writes (confine.h): no
// processes, no exit, and no path that leaves the run folder for the Lua libraries (gaitlab's
// own readers may read anywhere: they are bounded, and reading harms nothing)
constexpr const char* kPrelude = R"lua(
local error, type = error, type
local function outside(p)
  return type(p) == "string" and (p:sub(1, 1) == "/" or ("/" .. p .. "/"):find("/../", 1, true))
end
local function inside(name, fn)
  return function(p, ...)
    if outside(p) then error(name .. ": the fuzzer allows paths inside the run folder only", 2) end
    return fn(p, ...)
  end
end
local function refuse(name)
  return function() error(name .. " is not available in the fuzzer", 2) end
end
io.open = inside("io.open", io.open)
io.lines = inside("io.lines", io.lines)
io.input = inside("io.input", io.input)
io.output = inside("io.output", io.output)
dofile = inside("dofile", dofile)
loadfile = inside("loadfile", loadfile)
os.execute = refuse("os.execute")
os.exit = refuse("os.exit")
io.popen = refuse("io.popen")
package.loadlib = refuse("package.loadlib")
package.cpath = ""
package.path = "./?.lua"
local tmp = 0
os.tmpname = function() tmp = tmp + 1 return "tmp" .. tmp end
)lua";

// the file a shell command hidden in a generated string creates (script_gen.cpp)
constexpr const char* kInjected = "gaitlab_injected";

[[noreturn]] void finding(const std::string& what) {
    std::fprintf(stderr, "lua_fuzz: FINDING: %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

// __fuzz_finding(message): a strict script's own check failed
int l_fuzz_finding(lua_State* L) {
    const char* message = luaL_tolstring(L, 1, nullptr);
    finding(message);
}

// whether a file named `name` is anywhere in `dir`
bool contains_file(const fs::path& dir, const std::string& name) {
    std::error_code ec;
    for (fs::recursive_directory_iterator
             it(dir, fs::directory_options::skip_permission_denied, ec),
         end;
         !ec && it != end; it.increment(ec)) {
        if (it->path().filename() == name) return true;
    }
    return false;
}

}  // namespace

// interrupts the host of the running script once its wall time is up
struct Runner::Watchdog {
    std::mutex mutex;
    std::condition_variable wake;
    scripting::LuaHost* host = nullptr;
    std::chrono::steady_clock::time_point deadline;
    bool fired = false;
    bool quit = false;
    std::thread thread{[this] { loop(); }};  // last: starts once the rest is initialized

    ~Watchdog() {
        {
            std::lock_guard<std::mutex> lock(mutex);
            quit = true;
        }
        wake.notify_all();
        thread.join();
    }

    void loop() {
        std::unique_lock<std::mutex> lock(mutex);
        while (!quit) {
            if (host == nullptr) {
                wake.wait(lock);
            } else if (std::chrono::steady_clock::now() >= deadline) {
                host->interrupt(SIGALRM);
                fired = true;
                host = nullptr;
            } else {
                wake.wait_until(lock, deadline);
            }
        }
    }

    void arm(scripting::LuaHost& h, double seconds) {
        {
            std::lock_guard<std::mutex> lock(mutex);
            host = &h;
            fired = false;
            deadline = std::chrono::steady_clock::now() +
                       std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                           std::chrono::duration<double>(seconds));
        }
        wake.notify_all();
    }

    // no interrupt after this returns; whether it interrupted the script
    bool disarm() {
        std::lock_guard<std::mutex> lock(mutex);
        host = nullptr;
        return fired;
    }
};

Runner::Runner(std::string fixtures) : fixtures_(std::move(fixtures)) {
    // scripts may read stdin (io.read(), dofile()): it is empty, never a terminal to wait on
    const int null = ::open("/dev/null", O_RDONLY);
    if (null >= 0) {
        dup2(null, STDIN_FILENO);
        if (null != STDIN_FILENO) close(null);
    }
    // a process that crashed leaves its folder behind: remove those of processes that are gone
    const fs::path tmp = fs::temp_directory_path();
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(tmp, ec)) {
        const std::string name = e.path().filename().string();
        int pid = 0;
        if (std::sscanf(name.c_str(), "gaitlab-lua-fuzz-%d-", &pid) == 1 && pid > 0 &&
            kill(pid, 0) != 0 && errno == ESRCH) {
            fs::remove_all(e.path(), ec);
        }
    }
    std::string tmpl =
        (tmp / ("gaitlab-lua-fuzz-" + std::to_string(getpid()) + "-XXXXXX")).string();
    if (mkdtemp(tmpl.data()) == nullptr) {
        std::perror("lua_fuzz: cannot make a temporary folder");
        std::exit(2);
    }
    base_ = fs::canonical(tmpl).string();
    watchdog_ = std::make_unique<Watchdog>();
}

Runner::~Runner() {
    release_writes();
    std::error_code ec;
    fs::remove_all(base_, ec);
}

RunResult Runner::run(const Script& script, const Limits& limits) {
    const std::string dir = base_ + "/run";
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directory(dir);
    if (!fixtures_.empty()) fs::copy(fixtures_, dir, fs::copy_options::recursive, ec);
    const fs::path previous = fs::current_path();
    fs::current_path(dir);

    RunResult result;
    {
        scripting::LuaHost host(limits.memory);
        host.set_print(verbose_);
        if (!verbose_) host.set_reporter([](const std::string&) {});
        scripting::RecordSettings recording;
        recording.name = "fuzz";  // a simulation that asks to record goes under runs/ here
        host.set_recording(recording);
        long ticks = 0;
        host.on_simulation([&ticks, &limits](Simulation& sim, int) {
            sim.add_pre_tick([&ticks, &limits](Simulation&) {
                if (++ticks > limits.ticks) throw Error("the fuzzer's tick budget is spent");
            });
        });
        lua_State* L = host.state();
        if (script.strict) {
            lua_pushcfunction(L, l_fuzz_finding);
            lua_setglobal(L, "__fuzz_finding");
        }
        host.run_string(kPrelude, "=fuzz_prelude");

        confine_writes(dir);
        watchdog_->arm(host, limits.seconds);
        try {
            host.run_string(script.code, "=fuzz");
        } catch (const scripting::ScriptError& e) {
            result.outcome = Outcome::failed;
            result.message = e.what();
        }
        if (watchdog_->disarm() && result.outcome == Outcome::failed &&
            result.message.rfind("interrupted (", 0) == 0) {
            result.outcome = Outcome::interrupted;
        }
        try {
            host.finish();
        } catch (const IoError&) {
            // a recording whose last write failed (a refused folder, say): reported, not lost
        }
        // the host closes here, still confined: finalizers may write
    }
    release_writes();
    const std::vector<std::string> refused = refused_writes();
    fs::current_path(previous);

    if (contains_file(dir, kInjected)) {
        finding("a file named " + std::string(kInjected) +
                " appeared: a string of the script ran as a shell command");
    }
    if (script.strict && !refused.empty()) {
        std::string list;
        for (const std::string& r : refused)
            list += "\n  " + r;
        finding("a strict script wrote outside its folder " + dir + ":" + list);
    }
    fs::remove_all(dir, ec);
    return result;
}

}  // namespace gaitlab::fuzz
