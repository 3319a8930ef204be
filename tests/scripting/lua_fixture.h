// The Lua fixture of the scripting tests: runs snippets in a LuaHost, checks that every call
// leaves the Lua stack as it found it, and returns error messages for exact comparison.
#pragma once

#include <lua.hpp>

#include <string>

#include "gaitlab/scripting/lua_host.h"

namespace gaitlab::test {

/// Folder of the Lua files the scripting tests use (tests/scripting/lua).
std::string lua_dir();

class LuaFixture {
  public:
    LuaFixture();

    lua_State* L() const { return host.state(); }

    /// Runs `code` as chunk "=test" (messages start with "test:LINE: "); the stack must be
    /// balanced afterwards, whether the chunk succeeds or throws ScriptError.
    void run(const std::string& code);
    /// Runs `code`, which must fail; returns the error message (FAILs if it succeeds).
    std::string error_of(const std::string& code);
    /// The ScriptError `code` raises (FAILs if it succeeds).
    scripting::ScriptError script_error_of(const std::string& code);

    /// Evaluates `expr` (in the globals, after earlier run() calls) as a number, integer,
    /// string or boolean; the value must have that type.
    double number(const std::string& expr);
    long long integer(const std::string& expr);
    std::string string(const std::string& expr);
    bool boolean(const std::string& expr);

    /// Calls the function `fn` (a Lua expression) directly with lua_pcall and the arguments
    /// produced by the Lua expression list `args`; checks that exactly `nresults` values are
    /// left above the previous top and pops them. Returns the error message, "" on success.
    std::string pcall(const std::string& fn, const std::string& args, int nresults);

    scripting::LuaHost host;

  private:
    // pushes the values of a Lua expression list; returns how many
    int push_values(const std::string& exprs);
};

/// The state of an interpreter that did require "gaitlab" (what gaitlab/core.so opens), here
/// with the Lua core of the test: the interpreter's own libraries, gaitlab as the global
/// `gaitlab`.
struct InterpreterState {
    InterpreterState();
    ~InterpreterState();
    InterpreterState(const InterpreterState&) = delete;
    InterpreterState& operator=(const InterpreterState&) = delete;
    /// Runs `code` as chunk "=i"; its errors are ScriptError.
    void run(const std::string& code);

    lua_State* L;
};

}  // namespace gaitlab::test
