// The limits Lua code runs under, so that no script can hang or crash the process: instruction
// budgets (a controller's step, a controller file's top level, its hooks), interrupts (a signal
// or Ctrl-C) and the memory a host's Lua state may use. A budget that runs out, or an
// interrupt, stops the Lua code at its next instruction and at every instruction after that,
// so pcall and xpcall cannot swallow it: the error reaches the C++ caller that set the limit.
//
// The guard puts its debug hook on a thread only while a budget or an interrupt needs it, and
// gives back the hook it found there (a debugger's, a profiler's, lua.c's Ctrl-C hook) when it
// is done; it never removes a hook that it did not set.
#pragma once

#include <lua.hpp>

#include <atomic>
#include <cstddef>
#include <string>
#include <vector>

namespace gaitlab::scripting {

/// Instructions the top level of a controller file, its snapshot and its on_reload may run.
inline constexpr long long kLoadInstructionBudget = 100'000'000;

/// Whose Lua state gaitlab is loaded into.
enum class StateOwner {
    /// a LuaHost's (gaitlab run, the console, a C++ program): gaitlab owns the state, its
    /// globals and its signals
    gaitlab,
    /// a Lua interpreter's that did `require "gaitlab"` (lua5.4): the state, its globals, its
    /// hooks and its signals are the interpreter's
    interpreter,
};

class Guard {
  public:
    /// The guard of L's state; throws Error if gaitlab is not loaded in it.
    static Guard& of(lua_State* L);
    /// The same, or nullptr: for hooks and C functions, which must not throw.
    static Guard* find(lua_State* L);
    /// Creates it and keeps it in the registry, and makes coroutines run under the budget and
    /// interrupts of the code that resumes them (coroutine.resume and coroutine.wrap) and
    /// xpcall's message handlers step aside once the code must stop (xpcall): without them a
    /// controller's step could hang the process. These replace the globals, in an interpreter's
    /// state too; they behave as the standard ones while no budget or interrupt holds.
    static void install(lua_State* L, StateOwner owner);
    /// Pushes the guarded xpcall.
    static void push_xpcall(lua_State* L);

    StateOwner owner() const { return owner_; }

    /// Asks the Lua code of this state to stop (see interrupt_message); async-signal-safe.
    /// `L` is the state's main thread.
    void interrupt(lua_State* L, int signal);
    /// Whether the running code must stop: interrupted, or a budget is spent.
    bool stopping() const;
    /// The signal given to interrupt() (SIGINT ...), 0 if none.
    int interrupted() const { return signal_.load(); }
    /// The same, for a thread that watches it (an optimization the host runs stops on it).
    const std::atomic<int>& interrupt_signal() const { return signal_; }
    /// Forgets an interrupt (a console back at its prompt); `L` is the state's main thread.
    void clear_interrupt(lua_State* L);
    /// "interrupted (SIGINT)": the error Lua code stops with.
    std::string interrupt_message() const;
    /// The same into `out` (no allocation).
    void format_interrupt(char* out, std::size_t size) const;
    /// Notes the coroutine now running (so an interrupt reaches it); returns the previous one.
    lua_State* set_running(lua_State* co);

    /// Spends `instructions` of every budget that holds on thread L, for work done in C on the
    /// Lua code's behalf, which the hook does not count (pairs' sort): a budget spent stops the
    /// code with its message, naming the place of the Lua function that called the C one.
    /// Nothing when L's state has no guard or no budget holds. Raises a Lua error: call it
    /// where nothing with a destructor lives.
    static void charge(lua_State* L, long long instructions);

    /// Puts the guard's hook on thread T (keeping the hook T had, if it is another's).
    void set_hook(lua_State* T, int mask, int count);
    /// Takes the guard's hook off thread T, giving back the hook it replaced; a hook that is
    /// not the guard's stays.
    void release_hook(lua_State* T);
    /// Whether thread T runs under the guard's hook.
    static bool hooked(lua_State* T);
    /// Keeps the hook thread T has now (unless it is the guard's) to give it back when the
    /// guard's goes. `pin`: kept until unpin_hook(T), so that an interrupt (which cannot keep
    /// it: a signal handler may not allocate) may replace it and clear_interrupt() gives it
    /// back.
    void keep_hook(lua_State* T, bool pin);
    void unpin_hook(lua_State* T);

  private:
    friend class Budget;
    struct Frame {
        long long remaining;      // instructions left
        const std::string* what;  // whose budget: "controller 'wave'"
        const char* suffix;       // " in one step"
        long long limit;
        bool exhausted = false;
    };
    // the hook another party had on a thread when the guard put its own there
    struct Saved {
        lua_State* thread;
        lua_Hook hook;
        int mask;
        int count;
        bool pinned;
    };
    Saved* saved(lua_State* T);
    static void hook(lua_State* L, lua_Debug* ar);
    // takes `instructions` off every budget not yet spent; the outermost spent one, if any
    const Frame* spend(long long instructions);
    // raises "WHAT exceeded its instruction budget ..." for `spent`, at `ar` ("Sl" filled in)
    static void raise_spent(lua_State* L, const Frame& spent, const lua_Debug& ar);
    // installs the hook that the frames and the interrupt need on thread L (or removes it)
    void arm(lua_State* L);

    StateOwner owner_ = StateOwner::gaitlab;
    std::vector<Frame> frames_;  // innermost last
    std::vector<Saved> saved_;
    int interval_ = 0;  // the count the hook was last armed with
    std::atomic<int> signal_{0};
    std::atomic<lua_State*> running_{nullptr};  // the coroutine running now, if any
};

/// Runs the Lua calls made on thread L during its lifetime under a budget of `instructions`;
/// when they run out, the code stops with "WHAT exceeded its instruction budget of N
/// instructions SUFFIX (FILE:LINE)". Budgets nest: an inner one also spends the outer ones'.
class Budget {
  public:
    /// `what` and `suffix` must outlive the budget. Throws Error if gaitlab is not loaded.
    Budget(lua_State* L, long long instructions, const std::string& what, const char* suffix = "");
    ~Budget();
    Budget(const Budget&) = delete;
    Budget& operator=(const Budget&) = delete;

  private:
    lua_State* L_;
    Guard& guard_;
};

/// While it lives (around sim:run and sim:step) in an interpreter's state: SIGINT (Ctrl-C)
/// interrupts the state as LuaHost::interrupt does, since the interpreter's own handler (lua.c
/// stops the Lua code at its next instruction) cannot stop a simulation that steps in C++.
/// After a first SIGINT the interpreter's handler is back, so a second one does what it did
/// before. When the outermost scope ends the interrupt is forgotten: its error ("interrupted
/// (SIGINT)") goes on to the script like any other, and the interpreter runs code again.
/// Does nothing in a state gaitlab owns (its host takes the signals), nor where SIGINT is
/// ignored.
class InterruptScope {
  public:
    explicit InterruptScope(lua_State* L);
    ~InterruptScope();
    InterruptScope(const InterruptScope&) = delete;
    InterruptScope& operator=(const InterruptScope&) = delete;

  private:
    Guard* guard_ = nullptr;  // set if this scope took SIGINT
    lua_State* main_ = nullptr;
};

/// A lua_Alloc that refuses to let a state hold more than `limit` bytes: past it an allocation
/// fails and Lua raises "not enough memory", which scripts and controllers see as an error.
struct MemoryLimit {
    std::size_t limit;
    std::size_t used = 0;
    static void* alloc(void* ud, void* ptr, std::size_t osize, std::size_t nsize);
};

}  // namespace gaitlab::scripting
