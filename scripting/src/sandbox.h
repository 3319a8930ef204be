// The sandbox controller files run in (docs/lua-controllers.md, "Safety"). What a sandboxed file
// can do is what its environment holds: the basic functions, copies of math, string, table and
// utf8, and its own gaitlab.controller. It cannot:
//   - reach files, processes, the debug library or the script's globals (none are in it);
//   - change anything it did not make: copies of the libraries, a getmetatable that only shows
//     the metatables it set itself (so not the strings' one, nor gaitlab's), no __gc
//     finalizers (they would run outside every budget);
//   - load a file outside the sandbox, or write one outside its own folder;
//   - run longer than its budget: every Lua instruction counts (guard.h), and the string
//     pattern functions refuse a pattern whose worst case over its subject is too long, since
//     matching runs in C where no instruction is counted.
#pragma once

#include <lua.hpp>

#include <string>

namespace gaitlab::scripting {

/// Worst-case matching steps a pattern may cost in sandboxed code.
inline constexpr double kMaxPatternSteps = 1e9;

/// Pushes a fresh environment for the sandboxed controller file `chunk` (its path, or
/// "template/NAME.lua"), and marks the chunk as sandboxed.
void push_sandbox(lua_State* L, const std::string& chunk);

/// Whether the innermost Lua function calling the running C function belongs to a sandboxed
/// chunk.
bool called_from_sandbox(lua_State* L);

/// Makes the pattern functions of the string library (string.find, match, gmatch, gsub, which
/// strings also reach as methods) refuse too costly patterns when sandboxed code calls them.
/// Called once per Lua state, after the standard libraries are open.
void guard_patterns(lua_State* L);

/// The worst-case number of steps matching `pattern` against a subject of `n` characters may
/// take (Lua's matcher backtracks: each repeated item can multiply the work by n).
double pattern_cost(const std::string& pattern, double n);

}  // namespace gaitlab::scripting
