// Runs one fuzzed Lua script the way the Lua fuzzer and its replay test do: in a fresh
// LuaHost with a small memory limit, in a folder of its own (the current directory while it
// runs, removed afterwards, the only place it may write), for a bounded number of simulation
// ticks and a bounded wall time. A Lua error is the expected outcome of most scripts; what
// the runner cannot tell from a normal run (a crash, a sanitizer report, an exception other
// than ScriptError, a hang) ends the process, and so do the findings it checks itself (see
// Runner::run).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "script_gen.h"

namespace gaitlab::fuzz {

struct Limits {
    /// Bytes the script's Lua state may hold.
    std::size_t memory = std::size_t{64} << 20;
    /// Wall time after which the script is interrupted (LuaHost::interrupt), s.
    double seconds = 2;
    /// Physics ticks over all the simulations of one script; past them every step fails.
    long ticks = 3000;
};

enum class Outcome {
    finished,     ///< the script ran to its end
    failed,       ///< it raised a Lua error (ScriptError)
    interrupted,  ///< the watchdog stopped it
};

struct RunResult {
    Outcome outcome = Outcome::finished;
    std::string message;  ///< the error's message
};

class Runner {
  public:
    /// `fixtures`: a folder whose files are copied into every run's folder (the files that
    /// the examples and the corpus scripts name: controllers/, robots/, walk/, terrain.png
    /// ...), "" for none. Makes stdin empty for good: scripts may read it.
    explicit Runner(std::string fixtures);
    ~Runner();
    Runner(const Runner&) = delete;
    Runner& operator=(const Runner&) = delete;

    /// Runs `script`. Aborts the process with a message on stderr (a finding) when:
    /// - a file named gaitlab_injected appeared: a string ran as a shell command;
    /// - a strict script (script_gen.h) wrote outside its folder (others are only refused);
    /// - a strict script called __fuzz_finding(message) (its own checks: a saved robot that
    ///   does not load again ...).
    RunResult run(const Script& script, const Limits& limits = Limits());
    /// Whether scripts' print() and the host's reports go to stdout and stderr (default: no).
    void set_verbose(bool verbose) { verbose_ = verbose; }

  private:
    struct Watchdog;
    std::string fixtures_;
    std::string base_;  // this process's folder, holding the run folders
    bool verbose_ = false;
    std::unique_ptr<Watchdog> watchdog_;
};

}  // namespace gaitlab::fuzz
