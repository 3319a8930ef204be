// The limits Lua code runs under, so that no script can hang or crash the process: instruction
// budgets (a controller's step, a controller file's top level, its hooks), interrupts (a signal
// or Ctrl-C) and the memory a host's Lua state may use. A budget that runs out, or an
// interrupt, stops the Lua code at its next instruction and at every instruction after that,
// so pcall and xpcall cannot swallow it: the error reaches the C++ caller that set the limit.
#pragma once

#include <lua.hpp>

#include <atomic>
#include <cstddef>
#include <string>
#include <vector>

namespace gaitlab::scripting {

/// Instructions the top level of a controller file, its snapshot and its on_reload may run.
inline constexpr long long kLoadInstructionBudget = 100'000'000;

class Guard {
  public:
    /// The guard of L's state (created by luaopen_gaitlab).
    static Guard& of(lua_State* L);
    /// Creates it, keeps it in the registry and makes coroutines run under the budget and
    /// interrupts of the code that resumes them, and xpcall's message handlers step aside
    /// once the code must stop.
    static void install(lua_State* L);

    /// Asks the Lua code of this state to stop (see interrupt_message); async-signal-safe.
    /// `L` is the state's main thread.
    void interrupt(lua_State* L, int signal);
    /// Whether the running code must stop: interrupted, or a budget is spent.
    bool stopping() const;
    /// The signal given to interrupt() (SIGINT ...), 0 if none.
    int interrupted() const { return signal_.load(); }
    /// Forgets an interrupt (a console back at its prompt); `L` is the state's main thread.
    void clear_interrupt(lua_State* L);
    /// "interrupted (SIGINT)": the error Lua code stops with.
    std::string interrupt_message() const;
    /// The same into `out` (no allocation).
    void format_interrupt(char* out, std::size_t size) const;
    /// Notes the coroutine now running (so an interrupt reaches it); returns the previous one.
    lua_State* set_running(lua_State* co);

  private:
    friend class Budget;
    struct Frame {
        long long remaining;      // instructions left
        const std::string* what;  // whose budget: "controller 'wave'"
        const char* suffix;       // " in one step"
        long long limit;
        bool exhausted = false;
    };
    static void hook(lua_State* L, lua_Debug* ar);
    // installs the hook that the frames and the interrupt need on thread L (or removes it)
    void arm(lua_State* L);

    std::vector<Frame> frames_;  // innermost last
    int interval_ = 0;           // the count the hook was last armed with
    std::atomic<int> signal_{0};
    std::atomic<lua_State*> running_{nullptr};  // the coroutine running now, if any
};

/// Runs the Lua calls made on thread L during its lifetime under a budget of `instructions`;
/// when they run out, the code stops with "WHAT exceeded its instruction budget of N
/// instructions SUFFIX (FILE:LINE)". Budgets nest: an inner one also spends the outer ones'.
class Budget {
  public:
    /// `what` and `suffix` must outlive the budget.
    Budget(lua_State* L, long long instructions, const std::string& what, const char* suffix = "");
    ~Budget();
    Budget(const Budget&) = delete;
    Budget& operator=(const Budget&) = delete;

  private:
    lua_State* L_;
    Guard& guard_;
};

/// A lua_Alloc that refuses to let a state hold more than `limit` bytes: past it an allocation
/// fails and Lua raises "not enough memory", which scripts and controllers see as an error.
struct MemoryLimit {
    std::size_t limit;
    std::size_t used = 0;
    static void* alloc(void* ud, void* ptr, std::size_t osize, std::size_t nsize);
};

}  // namespace gaitlab::scripting
