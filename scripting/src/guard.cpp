#include "guard.h"

#include <signal.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "lua_util.h"

namespace gaitlab::scripting {

namespace {

constexpr const char* kGuardKey = "gaitlab.guard";
constexpr const char* kGuardType = "gaitlab.Guard";

// the hook fires at least this often while a budget runs, so a budget is spent in steps of at
// most this many instructions
constexpr int kChunk = 1 << 16;

const char* signal_name(int s) {
    switch (s) {
        case SIGINT:
            return "SIGINT";
        case SIGTERM:
            return "SIGTERM";
        case SIGHUP:
            return "SIGHUP";
        case SIGPIPE:
            return "SIGPIPE";
        case SIGALRM:
            return "SIGALRM";
        default:
            return nullptr;
    }
}

// coroutine.resume(co, ...) that first gives the coroutine the hook of the code resuming it
// (or takes the guard's away), so a budget or an interrupt also holds inside coroutines made
// before it started; upvalue 1 is the standard resume. No C++ object is alive here: the
// errors of the resume (its arguments, an interrupt at the call) are raised after it
int guarded_resume(lua_State* L) {
    luaL_checktype(L, 1, LUA_TTHREAD);  // as the standard resume says it
    lua_State* co = lua_tothread(L, 1);
    Guard* g = Guard::find(L);
    if (!g) return luaL_error(L, "gaitlab is not loaded in this Lua state");
    if (Guard::hooked(L)) {
        g->set_hook(co, lua_gethookmask(L), lua_gethookcount(L));
    } else {
        g->release_hook(co);
    }
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    const int nargs = lua_gettop(L) - 1;
    lua_State* outer = g->set_running(co);
    const int status = lua_pcall(L, nargs, LUA_MULTRET, 0);
    g->set_running(outer);
    if (status != LUA_OK) return lua_error(L);
    return lua_gettop(L);
}

// the function coroutine.wrap returns: resumes its coroutine (upvalue 1) through
// guarded_resume (upvalue 2) and raises its errors, as the standard wrap does
int wrapped_call(lua_State* L) {
    const int nargs = lua_gettop(L);
    lua_pushvalue(L, lua_upvalueindex(2));
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_rotate(L, 1, 2);
    lua_call(L, nargs + 1, LUA_MULTRET);
    if (!lua_toboolean(L, 1)) {
        lua_State* co = lua_tothread(L, lua_upvalueindex(1));
        if (lua_type(L, 2) == LUA_TSTRING) {  // add where the call happened, as Lua does
            luaL_where(L, 1);
            lua_insert(L, 2);
            lua_concat(L, 2);
        }
        // a dead coroutine closes its to-be-closed variables, as the standard wrap does
        if (co && lua_status(co) != LUA_OK && lua_status(co) != LUA_YIELD) lua_resetthread(co);
        return lua_error(L);
    }
    return lua_gettop(L) - 1;
}

// coroutine.wrap(f): upvalue 1 is the standard create, upvalue 2 guarded_resume
int guarded_wrap(lua_State* L) {
    luaL_checktype(L, 1, LUA_TFUNCTION);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_pushvalue(L, 1);
    lua_call(L, 1, 1);
    lua_pushvalue(L, lua_upvalueindex(2));
    lua_pushcclosure(L, wrapped_call, 2);
    return 1;
}

// the message handler xpcall gets instead of the script's (upvalue 1): once the code must stop
// (a spent budget, an interrupt), the error passes through untouched. The script's handler
// would run with hooks off: the error was raised inside the hook, where Lua allows none.
int guarded_handler(lua_State* L) {
    const Guard* g = Guard::find(L);
    if (g && g->stopping()) {
        lua_settop(L, 1);
        return 1;
    }
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, 1);
    return 1;
}

// what xpcall returns once its call ended (or resumed after a yield)
int finish_xpcall(lua_State* L, int status, lua_KContext extra) {
    if (status != LUA_OK && status != LUA_YIELD) {
        lua_pushboolean(L, 0);
        lua_pushvalue(L, -2);
        return 2;
    }
    return lua_gettop(L) - static_cast<int>(extra);  // true and the call's results
}

// xpcall(f, handler, ...), with the handler guarded (yields inside f still work)
int guarded_xpcall(lua_State* L) {
    const int n = lua_gettop(L);
    luaL_checktype(L, 2, LUA_TFUNCTION);
    lua_pushvalue(L, 2);
    lua_pushcclosure(L, guarded_handler, 1);
    lua_replace(L, 2);
    lua_pushboolean(L, 1);  // the first result when f succeeds
    lua_pushvalue(L, 1);    // f
    lua_rotate(L, 3, 2);    // true, f, then f's arguments
    const int status = lua_pcallk(L, n - 2, LUA_MULTRET, 2, 2, finish_xpcall);
    return finish_xpcall(L, status, 2);
}

}  // namespace

bool Guard::stopping() const {
    if (signal_.load() != 0) return true;
    for (const Frame& f : frames_) {
        if (f.exhausted) return true;
    }
    return false;
}

lua_State* Guard::set_running(lua_State* co) {
    return running_.exchange(co);
}

Guard* Guard::find(lua_State* L) {
    lua_getfield(L, LUA_REGISTRYINDEX, kGuardKey);
    auto* g = static_cast<Guard*>(luaL_testudata(L, -1, kGuardType));
    lua_pop(L, 1);
    return g;
}

Guard& Guard::of(lua_State* L) {
    Guard* g = find(L);
    if (!g) throw Error("gaitlab is not loaded in this Lua state");
    return *g;
}

bool Guard::hooked(lua_State* T) {
    return lua_gethook(T) == hook;
}

void Guard::push_xpcall(lua_State* L) {
    lua_pushcfunction(L, guarded_xpcall);
}

void Guard::install(lua_State* L, StateOwner owner) {
    if (luaL_newmetatable(L, kGuardType)) {
        lua_pushcfunction(L, [](lua_State* S) -> int {
            if (auto* g = static_cast<Guard*>(luaL_testudata(S, 1, kGuardType))) g->~Guard();
            // a second call (by hand, through the debug library) finds no metatable
            lua_pushnil(S);
            lua_setmetatable(S, 1);
            return 0;
        });
        lua_setfield(L, -2, "__gc");
        lua_pushboolean(L, 0);
        lua_setfield(L, -2, "__metatable");
    }
    lua_pop(L, 1);
    new (lua_newuserdatauv(L, sizeof(Guard), 0)) Guard();
    luaL_setmetatable(L, kGuardType);
    static_cast<Guard*>(lua_touserdata(L, -1))->owner_ = owner;
    lua_setfield(L, LUA_REGISTRYINDEX, kGuardKey);
    // the messages of the usual interrupts, kept so that Lua has them interned
    lua_newtable(L);
    for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGALRM}) {
        lua_pushfstring(L, "interrupted (%s)", signal_name(s));
        lua_rawseti(L, -2, s);
    }
    lua_setfield(L, LUA_REGISTRYINDEX, "gaitlab.interrupt_messages");

    push_xpcall(L);
    raw_setglobal(L, "xpcall");
    if (raw_getglobal(L, "coroutine") == LUA_TTABLE) {
        raw_getfield(L, -1, "resume");
        if (lua_iscfunction(L, -1)) {
            lua_pushcclosure(L, guarded_resume, 1);
            raw_getfield(L, -2, "create");
            lua_pushvalue(L, -2);
            lua_pushcclosure(L, guarded_wrap, 2);
            raw_setfield(L, -3, "wrap");
            raw_setfield(L, -2, "resume");
        } else {
            lua_pop(L, 1);
        }
    }
    lua_pop(L, 1);
}

void Guard::format_interrupt(char* out, std::size_t size) const {
    const int s = signal_.load();
    if (const char* name = signal_name(s)) {
        std::snprintf(out, size, "interrupted (%s)", name);
    } else {
        std::snprintf(out, size, "interrupted (signal %d)", s);
    }
}

std::string Guard::interrupt_message() const {
    char message[64];
    format_interrupt(message, sizeof message);
    return message;
}

void Guard::interrupt(lua_State* L, int signal) {
    signal_.store(signal);
    // as lua.c does at Ctrl-C: a hook set asynchronously stops the code at its next instruction
    lua_sethook(L, hook, LUA_MASKCALL | LUA_MASKRET | LUA_MASKCOUNT, 1);
    if (lua_State* co = running_.load()) {
        lua_sethook(co, hook, LUA_MASKCALL | LUA_MASKRET | LUA_MASKCOUNT, 1);
    }
}

void Guard::clear_interrupt(lua_State* L) {
    signal_.store(0);
    arm(L);
}

Guard::Saved* Guard::saved(lua_State* T) {
    for (Saved& x : saved_) {
        if (x.thread == T) return &x;
    }
    return nullptr;
}

void Guard::keep_hook(lua_State* T, bool pin) {
    Saved* s = saved(T);
    if (!s) {
        if (hooked(T) && !pin) return;  // nothing to keep (and a hook must not allocate)
        try {
            saved_.push_back(Saved{T, nullptr, 0, 0, false});
        } catch (const std::bad_alloc&) {
            return;  // called from C functions Lua calls: the hook is lost, nothing thrown
        }
        s = &saved_.back();
    }
    if (!hooked(T)) {
        s->hook = lua_gethook(T);
        s->mask = lua_gethookmask(T);
        s->count = lua_gethookcount(T);
    }
    s->pinned = s->pinned || pin;
}

void Guard::unpin_hook(lua_State* T) {
    if (Saved* s = saved(T)) {
        s->pinned = false;
        if (!hooked(T)) saved_.erase(saved_.begin() + (s - saved_.data()));
    }
}

void Guard::set_hook(lua_State* T, int mask, int count) {
    keep_hook(T, false);
    lua_sethook(T, hook, mask, count);
}

void Guard::release_hook(lua_State* T) {
    Saved* s = saved(T);
    if (hooked(T)) {
        if (s) {
            lua_sethook(T, s->hook, s->mask, s->count);
        } else {
            lua_sethook(T, nullptr, 0, 0);
        }
    }
    if (s && !s->pinned) saved_.erase(saved_.begin() + (s - saved_.data()));
}

void Guard::arm(lua_State* L) {
    if (signal_.load() != 0) {
        set_hook(L, LUA_MASKCALL | LUA_MASKRET | LUA_MASKCOUNT, 1);
        return;
    }
    bool exhausted = false;
    long long remaining = kChunk;
    for (const Frame& f : frames_) {
        exhausted = exhausted || f.exhausted;
        remaining = std::min(remaining, f.remaining);
    }
    if (frames_.empty()) {
        interval_ = 0;
        release_hook(L);
        return;
    }
    interval_ = exhausted ? 1 : static_cast<int>(std::max<long long>(remaining, 1));
    set_hook(L, LUA_MASKCOUNT, interval_);
}

void Guard::hook(lua_State* L, lua_Debug* ar) {
    Guard* found = find(L);
    if (!found) {
        lua_sethook(L, nullptr, 0, 0);  // a state gaitlab has left
        return;
    }
    Guard& g = *found;
    if (g.signal_.load() != 0) {
        // every instruction from now on fails, so no pcall can swallow the interrupt. The
        // message was made at install: pushing it again allocates nothing, even at the limit
        lua_sethook(L, hook, LUA_MASKCALL | LUA_MASKRET | LUA_MASKCOUNT, 1);
        char message[64];
        g.format_interrupt(message, sizeof message);
        lua_pushstring(L, message);
        lua_error(L);
    }
    if (g.frames_.empty() || ar->event != LUA_HOOKCOUNT) return;
    const Frame* spent = g.spend(std::max(g.interval_, 1));
    g.arm(L);
    if (!spent) return;
    lua_getinfo(L, "Sl", ar);
    raise_spent(L, *spent, *ar);
}

const Guard::Frame* Guard::spend(long long instructions) {
    const Frame* spent = nullptr;
    for (Frame& f : frames_) {
        if (!f.exhausted) {
            f.remaining -= instructions;
            f.exhausted = f.remaining <= 0;
        }
        if (f.exhausted && !spent) spent = &f;
    }
    return spent;
}

void Guard::raise_spent(lua_State* L, const Frame& spent, const lua_Debug& ar) {
    lua_pushfstring(L, "%s exceeded its instruction budget of %I instructions%s (%s:%d)",
                    spent.what->c_str(), static_cast<lua_Integer>(spent.limit), spent.suffix,
                    ar.source[0] == '@' ? ar.source + 1 : ar.short_src, ar.currentline);
    lua_error(L);
}

void Guard::charge(lua_State* L, long long instructions) {
    Guard* g = find(L);
    if (!g || g->frames_.empty()) return;
    const Frame* spent = g->spend(instructions);
    g->arm(L);
    if (!spent) return;
    // level 0 is the C function that does the work, level 1 the Lua code that called it
    lua_Debug ar{};
    if (!lua_getstack(L, 1, &ar) || !lua_getinfo(L, "Sl", &ar)) {
        ar.source = "=?";
        std::snprintf(ar.short_src, sizeof ar.short_src, "?");
        ar.currentline = -1;
    }
    raise_spent(L, *spent, ar);
}

Budget::Budget(lua_State* L, long long instructions, const std::string& what, const char* suffix)
    : L_(L), guard_(Guard::of(L)) {
    guard_.frames_.push_back(Guard::Frame{instructions, &what, suffix, instructions, false});
    guard_.arm(L_);
}

Budget::~Budget() {
    guard_.frames_.pop_back();
    guard_.arm(L_);
}

namespace {

// the state whose sim:run or sim:step takes SIGINT now (see InterruptScope), and what SIGINT
// did before: written before the handler is installed, read by it
std::atomic<Guard*> g_interruptible{nullptr};
std::atomic<lua_State*> g_interruptible_state{nullptr};
struct sigaction g_previous_sigint;

extern "C" void on_interpreter_sigint(int sig) {
    // a second Ctrl-C does what it did before this scope (lua.c's handler, or the default)
    sigaction(SIGINT, &g_previous_sigint, nullptr);
    Guard* g = g_interruptible.load();
    lua_State* L = g_interruptible_state.load();
    if (g && L) g->interrupt(L, sig);
}

}  // namespace

InterruptScope::InterruptScope(lua_State* L) {
    Guard* g = Guard::find(L);
    if (!g || g->owner() != StateOwner::interpreter) return;
    Guard* none = nullptr;
    if (!g_interruptible.compare_exchange_strong(none, g)) return;  // an outer scope has it
    struct sigaction current {};
    sigaction(SIGINT, nullptr, &current);
    if (!(current.sa_flags & SA_SIGINFO) && current.sa_handler == SIG_IGN) {
        g_interruptible.store(nullptr);  // SIGINT is ignored (nohup, a background job)
        return;
    }
    guard_ = g;
    main_ = main_thread(L);
    // an interrupt replaces the main thread's hook: keep the interpreter's to give it back
    g->keep_hook(main_, true);
    g_previous_sigint = current;
    g_interruptible_state.store(main_);
    struct sigaction sa {};
    sa.sa_handler = on_interpreter_sigint;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
}

InterruptScope::~InterruptScope() {
    if (!guard_) return;
    struct sigaction current {};
    sigaction(SIGINT, nullptr, &current);
    if (!(current.sa_flags & SA_SIGINFO) && current.sa_handler == on_interpreter_sigint) {
        sigaction(SIGINT, &g_previous_sigint, nullptr);
    }
    g_interruptible_state.store(nullptr);
    g_interruptible.store(nullptr);
    // the error it caused is on its way to the script; the interpreter's hook comes back
    if (guard_->interrupted() != 0) guard_->clear_interrupt(main_);
    guard_->unpin_hook(main_);
}

void* MemoryLimit::alloc(void* ud, void* ptr, std::size_t osize, std::size_t nsize) {
    auto* m = static_cast<MemoryLimit*>(ud);
    const std::size_t old = ptr ? osize : 0;  // without ptr, osize tells the object's kind
    if (nsize == 0) {
        std::free(ptr);
        m->used -= old;
        return nullptr;
    }
    if (nsize > old && nsize - old > m->limit - m->used) return nullptr;
    void* p = std::realloc(ptr, nsize);
    if (p) m->used = m->used - old + nsize;
    return p;
}

}  // namespace gaitlab::scripting
