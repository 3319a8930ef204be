#include "guard.h"

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <fmt/format.h>

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

// coroutine.resume(co, ...) that first gives the coroutine the hook of the code resuming it,
// so a budget or an interrupt also holds inside coroutines made before it started; upvalue 1
// is the standard resume
int guarded_resume(lua_State* L) {
    luaL_checktype(L, 1, LUA_TTHREAD);  // checked here: the call below raises nothing else
    lua_State* co = lua_tothread(L, 1);
    Guard& g = Guard::of(L);
    lua_sethook(co, lua_gethook(L), lua_gethookmask(L), lua_gethookcount(L));
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    const int nargs = lua_gettop(L) - 1;
    struct Running {  // restored however the call ends
        Guard& g;
        lua_State* outer;
        ~Running() { g.set_running(outer); }
    } running{g, g.set_running(co)};
    lua_call(L, nargs, LUA_MULTRET);
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
    if (Guard::of(L).stopping()) {
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

Guard& Guard::of(lua_State* L) {
    lua_getfield(L, LUA_REGISTRYINDEX, kGuardKey);
    auto* g = static_cast<Guard*>(luaL_testudata(L, -1, kGuardType));
    lua_pop(L, 1);
    if (!g) luaL_error(L, "gaitlab is not loaded in this Lua state");
    return *g;
}

void Guard::install(lua_State* L) {
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
    lua_setfield(L, LUA_REGISTRYINDEX, kGuardKey);
    // the messages of the usual interrupts, kept so that Lua has them interned
    lua_newtable(L);
    for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGALRM}) {
        lua_pushfstring(L, "interrupted (%s)", signal_name(s));
        lua_rawseti(L, -2, s);
    }
    lua_setfield(L, LUA_REGISTRYINDEX, "gaitlab.interrupt_messages");

    lua_pushcfunction(L, guarded_xpcall);
    lua_setglobal(L, "xpcall");
    if (lua_getglobal(L, "coroutine") == LUA_TTABLE) {
        lua_getfield(L, -1, "resume");
        if (lua_iscfunction(L, -1)) {
            lua_pushcclosure(L, guarded_resume, 1);
            lua_getfield(L, -2, "create");
            lua_pushvalue(L, -2);
            lua_pushcclosure(L, guarded_wrap, 2);
            lua_setfield(L, -3, "wrap");
            lua_setfield(L, -2, "resume");
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

void Guard::arm(lua_State* L) {
    if (signal_.load() != 0) {
        lua_sethook(L, hook, LUA_MASKCALL | LUA_MASKRET | LUA_MASKCOUNT, 1);
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
        lua_sethook(L, nullptr, 0, 0);
        return;
    }
    interval_ = exhausted ? 1 : static_cast<int>(std::max<long long>(remaining, 1));
    lua_sethook(L, hook, LUA_MASKCOUNT, interval_);
}

void Guard::hook(lua_State* L, lua_Debug* ar) {
    Guard& g = of(L);
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
    const Frame* spent = nullptr;
    for (Frame& f : g.frames_) {
        if (!f.exhausted) {
            f.remaining -= std::max(g.interval_, 1);
            f.exhausted = f.remaining <= 0;
        }
        if (f.exhausted && !spent) spent = &f;
    }
    g.arm(L);
    if (!spent) return;
    lua_getinfo(L, "Sl", ar);
    lua_pushfstring(L, "%s exceeded its instruction budget of %I instructions%s (%s:%d)",
                    spent->what->c_str(), static_cast<lua_Integer>(spent->limit), spent->suffix,
                    ar->source[0] == '@' ? ar->source + 1 : ar->short_src, ar->currentline);
    lua_error(L);
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
