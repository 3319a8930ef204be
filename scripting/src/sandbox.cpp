#include "sandbox.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>

#include "fixed_order.h"
#include "guard.h"
#include "lua_util.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

// registry: source of every sandboxed chunk ("@path") -> true
constexpr const char* kSandboxedKey = "gaitlab.sandboxed";
// registry: the standard functions and libraries as gaitlab found them, which sandboxes copy
// (so a script that replaces a global does not hand its own function to a sandbox)
constexpr const char* kPristineKey = "gaitlab.pristine";

constexpr const char* kBaseFunctions[] = {
    "assert", "error",  "ipairs", "next",     "pairs",    "pcall", "print",  "rawequal", "rawget",
    "rawlen", "rawset", "select", "tonumber", "tostring", "type",  "xpcall", "_VERSION"};
constexpr const char* kLibraries[] = {"math", "string", "table", "utf8"};

// getmetatable(v) in a sandbox: as Lua's, but only the metatables the sandbox set itself
// (upvalue 1, a weak set) are shown; other values have none as far as it can tell
int sandbox_getmetatable(lua_State* L) {
    luaL_checkany(L, 1);
    if (!lua_getmetatable(L, 1)) {
        lua_pushnil(L);
        return 1;
    }
    if (raw_getfield(L, -1, "__metatable") != LUA_TNIL) return 1;  // a protected metatable
    lua_pop(L, 1);
    lua_pushvalue(L, -1);
    if (lua_rawget(L, lua_upvalueindex(1)) == LUA_TNIL) {
        lua_pushnil(L);
        return 1;
    }
    lua_pop(L, 1);
    return 1;
}

// setmetatable(t, mt) in a sandbox: as Lua's, without __gc (a finalizer runs at any time,
// where no budget holds); the metatables it sets become visible to its getmetatable
int sandbox_setmetatable(lua_State* L) {
    luaL_checktype(L, 1, LUA_TTABLE);
    const int t = lua_type(L, 2);
    luaL_argexpected(L, t == LUA_TNIL || t == LUA_TTABLE, 2, "nil or table");
    if (t == LUA_TTABLE) {
        if (raw_getfield(L, 2, "__gc") != LUA_TNIL) {  // raw, as the collector looks
            return luaL_error(L,
                              "__gc metamethods are not available in sandboxed controller "
                              "files");
        }
        lua_pop(L, 1);
    }
    if (luaL_getmetafield(L, 1, "__metatable") != LUA_TNIL) {
        return luaL_error(L, "cannot change a protected metatable");
    }
    lua_settop(L, 2);
    if (t == LUA_TTABLE) {
        lua_pushvalue(L, 2);
        lua_pushboolean(L, 1);
        lua_rawset(L, lua_upvalueindex(1));
    }
    lua_setmetatable(L, 1);
    return 1;
}

// which pattern function a guard wraps
enum PatternFunction { kFind, kMatch, kGmatch };

// the worst-case cost of the pattern call on the stack, for sandboxed callers (0 otherwise)
double call_cost(lua_State* L) {
    if (lua_type(L, 1) != LUA_TSTRING || lua_type(L, 2) != LUA_TSTRING) return 0;
    if (!called_from_sandbox(L)) return 0;
    const auto fn = static_cast<PatternFunction>(lua_tointeger(L, lua_upvalueindex(2)));
    if (fn == kFind && lua_toboolean(L, 4)) return 0;  // string.find(s, p, init, plain)
    size_t n = 0, np = 0;
    lua_tolstring(L, 1, &n);
    const char* p = lua_tolstring(L, 2, &np);
    try {
        std::string pattern(p, np);
        if (fn == kGmatch && !pattern.empty() && pattern[0] == '^') {
            pattern.insert(pattern.begin(), '%');  // no anchor: gmatch matches everywhere
        }
        return pattern_cost(pattern, static_cast<double>(n));
    } catch (const std::bad_alloc&) {
        return HUGE_VAL;  // refused: no exception may leave a C function Lua calls
    }
}

// the pattern functions of the string library, for sandboxed callers: upvalue 1 is the
// original, upvalue 2 which one it is
int guarded_pattern(lua_State* L) {
    const double cost = call_cost(L);
    if (cost > kMaxPatternSteps) {
        // no C++ object may be alive here: lua_error jumps over this frame
        char steps[32], most[32];
        std::snprintf(steps, sizeof steps, "%.0e", cost);
        std::snprintf(most, sizeof most, "%.0e", kMaxPatternSteps);
        size_t n = 0;
        lua_tolstring(L, 1, &n);
        luaL_where(L, 1);
        lua_pushfstring(L,
                        "pattern too costly for a sandboxed controller: matching it against %I "
                        "characters may take about %s steps (at most %s); use fewer repetitions "
                        "(*, +, -) or a shorter string",
                        static_cast<lua_Integer>(n), steps, most);
        lua_concat(L, 2);
        return lua_error(L);
    }
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

// copies the table at -1 into a new table left in its place
void replace_with_copy(lua_State* L) {
    lua_newtable(L);
    lua_pushnil(L);
    while (lua_next(L, -3) != 0) {
        lua_pushvalue(L, -2);
        lua_insert(L, -2);
        lua_rawset(L, -4);
    }
    lua_remove(L, -2);
}

}  // namespace

double pattern_cost(const std::string& p, double n) {
    const double positions = n + 1;
    double cost = 1;
    size_t i = 0;
    const bool anchored = !p.empty() && p[0] == '^';
    if (anchored) i = 1;
    while (i < p.size()) {
        const char c = p[i];
        if (c == '(' || c == ')') {
            ++i;
            continue;
        }
        if (c == '%' && i + 1 < p.size()) {
            const char k = p[i + 1];
            if (k == 'b') {  // %bxy scans ahead: linear
                cost *= positions;
                i += 4;
                continue;
            }
            if (k == 'f') {  // %f[set]: a frontier, no repetition
                i += 2;
                if (i < p.size() && p[i] == '[') {
                    ++i;
                    if (i < p.size() && p[i] == '^') ++i;
                    if (i < p.size() && p[i] == ']') ++i;
                    while (i < p.size() && p[i] != ']')
                        i += p[i] == '%' ? 2 : 1;
                    ++i;
                }
                continue;
            }
            if (k >= '0' && k <= '9') cost *= positions;  // a back reference compares a capture
            i += 2;
        } else if (c == '[') {
            ++i;
            if (i < p.size() && p[i] == '^') ++i;
            if (i < p.size() && p[i] == ']') ++i;
            while (i < p.size() && p[i] != ']')
                i += p[i] == '%' ? 2 : 1;
            ++i;
        } else {
            ++i;
        }
        if (i < p.size()) {
            if (p[i] == '*' || p[i] == '+' || p[i] == '-') {
                cost *= positions;
                ++i;
            } else if (p[i] == '?') {
                cost *= 2;
                ++i;
            }
        }
    }
    return anchored ? cost : cost * positions;
}

bool called_from_sandbox(lua_State* L) {
    lua_Debug ar;
    for (int level = 1; lua_getstack(L, level, &ar); ++level) {
        lua_getinfo(L, "S", &ar);
        if (ar.what[0] == 'C') continue;
        if (lua_getfield(L, LUA_REGISTRYINDEX, kSandboxedKey) != LUA_TTABLE) {
            lua_pop(L, 1);
            return false;
        }
        const bool sandboxed = lua_getfield(L, -1, ar.source) != LUA_TNIL;
        lua_pop(L, 2);
        return sandboxed;
    }
    return false;
}

void guard_patterns(lua_State* L) {
    // what sandboxes copy, as the libraries are now (read raw: an interpreter's globals may
    // have metamethods)
    lua_newtable(L);
    for (const char* name : kBaseFunctions) {
        if (std::strcmp(name, "xpcall") == 0) {
            Guard::push_xpcall(L);  // a message handler cannot outlast a spent budget
        } else if (std::strcmp(name, "pairs") == 0) {
            lua_pushcfunction(L, fixed_order_pairs);  // also under an interpreter's require
        } else {
            raw_getglobal(L, name);
        }
        raw_setfield(L, -2, name);
    }
    if (raw_getglobal(L, "string") == LUA_TTABLE) {
        for (const auto& [name, fn] :
             {std::pair{"find", kFind}, {"match", kMatch}, {"gmatch", kGmatch}, {"gsub", kMatch}}) {
            if (raw_getfield(L, -1, name) != LUA_TFUNCTION) {
                lua_pop(L, 1);
                continue;
            }
            lua_pushinteger(L, fn);
            lua_pushcclosure(L, guarded_pattern, 2);
            raw_setfield(L, -2, name);  // strings reach these as methods too
        }
    }
    lua_pop(L, 1);
    for (const char* lib : kLibraries) {
        if (raw_getglobal(L, lib) == LUA_TTABLE) {
            replace_with_copy(L);
            if (std::strcmp(lib, "table") == 0) {
                lua_pushcfunction(L, stable_sort);
                raw_setfield(L, -2, "sort");
            }
            raw_setfield(L, -2, lib);
        } else {
            lua_pop(L, 1);
        }
    }
    lua_setfield(L, LUA_REGISTRYINDEX, kPristineKey);
    lua_newtable(L);
    lua_setfield(L, LUA_REGISTRYINDEX, kSandboxedKey);
}

void push_sandbox(lua_State* L, const std::string& chunk) {
    lua_getfield(L, LUA_REGISTRYINDEX, kSandboxedKey);
    lua_pushboolean(L, 1);
    lua_setfield(L, -2, ("@" + chunk).c_str());
    lua_pop(L, 1);

    lua_newtable(L);
    const int env = lua_gettop(L);
    lua_getfield(L, LUA_REGISTRYINDEX, kPristineKey);
    const int pristine = lua_gettop(L);
    for (const char* name : kBaseFunctions) {
        lua_getfield(L, pristine, name);
        lua_setfield(L, env, name);
    }
    // copies, so a controller file cannot change the libraries everyone else uses
    for (const char* lib : kLibraries) {
        if (lua_getfield(L, pristine, lib) == LUA_TTABLE) {
            replace_with_copy(L);
        } else {
            lua_pop(L, 1);
            lua_newtable(L);
        }
        lua_setfield(L, env, lib);
    }
    lua_pop(L, 1);
    // the metatables this sandbox sets, which its getmetatable may show
    push_weak_table(L, "k");
    lua_pushvalue(L, -1);
    lua_pushcclosure(L, sandbox_getmetatable, 1);
    lua_setfield(L, env, "getmetatable");
    lua_pushcclosure(L, sandbox_setmetatable, 1);
    lua_setfield(L, env, "setmetatable");
    // gaitlab.controller of its own: loads stay sandboxed, writes stay in the file's folder
    lua_createtable(L, 0, 1);
    const std::filesystem::path folder = std::filesystem::path(chunk).parent_path();
    push_controller_api(L, folder.empty() ? "." : folder.string().c_str());
    lua_setfield(L, -2, "controller");
    lua_setfield(L, env, "gaitlab");
    lua_pushvalue(L, env);
    lua_setfield(L, env, "_G");
}

}  // namespace gaitlab::scripting
