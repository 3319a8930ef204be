#include "lua_fixture.h"

#include <catch2/catch.hpp>

#include <stdexcept>

#include "wrap.h"

namespace gaitlab::test {

using scripting::ScriptError;

std::string lua_dir() {
    return GAITLAB_SOURCE_DIR "/tests/scripting/lua";
}

namespace {

// a value the fixture keeps on the stack under every call: it must still be there, unchanged,
// at the same height afterwards
constexpr lua_Integer kSentinel = 424242;

void check_sentinel(lua_State* L, int top) {
    REQUIRE(lua_gettop(L) == top);
    REQUIRE(lua_isinteger(L, top));
    REQUIRE(lua_tointeger(L, top) == kSentinel);
}

}  // namespace

LuaFixture::LuaFixture() {
    lua_pushinteger(L(), kSentinel);
    REQUIRE(lua_gettop(L()) == 1);
}

void LuaFixture::run(const std::string& code) {
    const int top = lua_gettop(L());
    try {
        host.run_string(code, "=test");
    } catch (const ScriptError&) {
        check_sentinel(L(), top);
        throw;
    }
    check_sentinel(L(), top);
}

std::string LuaFixture::error_of(const std::string& code) {
    return script_error_of(code).what();
}

ScriptError LuaFixture::script_error_of(const std::string& code) {
    try {
        run(code);
    } catch (const ScriptError& e) {
        return e;
    }
    FAIL("expected an error from: " << code);
    throw std::logic_error("unreachable");
}

int LuaFixture::push_values(const std::string& exprs) {
    const int top = lua_gettop(L());
    if (exprs.empty()) return 0;
    const std::string code = "return " + exprs;
    REQUIRE(luaL_loadbufferx(L(), code.data(), code.size(), "=expr", "t") == LUA_OK);
    scripting::protected_call(L(), 0, LUA_MULTRET);
    return lua_gettop(L()) - top;
}

double LuaFixture::number(const std::string& expr) {
    const int top = lua_gettop(L());
    REQUIRE(push_values(expr) == 1);
    INFO(expr << " is a " << luaL_typename(L(), -1));
    REQUIRE(lua_type(L(), -1) == LUA_TNUMBER);
    const double v = lua_tonumber(L(), -1);
    lua_pop(L(), 1);
    check_sentinel(L(), top);
    return v;
}

long long LuaFixture::integer(const std::string& expr) {
    const int top = lua_gettop(L());
    REQUIRE(push_values(expr) == 1);
    INFO(expr << " is a " << luaL_typename(L(), -1));
    REQUIRE(lua_isinteger(L(), -1));
    const long long v = lua_tointeger(L(), -1);
    lua_pop(L(), 1);
    check_sentinel(L(), top);
    return v;
}

std::string LuaFixture::string(const std::string& expr) {
    const int top = lua_gettop(L());
    REQUIRE(push_values(expr) == 1);
    INFO(expr << " is a " << luaL_typename(L(), -1));
    REQUIRE(lua_type(L(), -1) == LUA_TSTRING);
    std::string v = lua_tostring(L(), -1);
    lua_pop(L(), 1);
    check_sentinel(L(), top);
    return v;
}

bool LuaFixture::boolean(const std::string& expr) {
    const int top = lua_gettop(L());
    REQUIRE(push_values(expr) == 1);
    INFO(expr << " is a " << luaL_typename(L(), -1));
    REQUIRE(lua_type(L(), -1) == LUA_TBOOLEAN);
    const bool v = lua_toboolean(L(), -1);
    lua_pop(L(), 1);
    check_sentinel(L(), top);
    return v;
}

std::string LuaFixture::pcall(const std::string& fn, const std::string& args, int nresults) {
    const int top = lua_gettop(L());
    REQUIRE(push_values(fn) == 1);
    REQUIRE(lua_type(L(), -1) == LUA_TFUNCTION);
    const int nargs = push_values(args);
    if (lua_pcall(L(), nargs, LUA_MULTRET, 0) != LUA_OK) {
        REQUIRE(lua_gettop(L()) == top + 1);
        std::string message = lua_isstring(L(), -1) ? lua_tostring(L(), -1) : "(no message)";
        lua_pop(L(), 1);
        check_sentinel(L(), top);
        return message;
    }
    INFO(fn << "(" << args << ")");
    REQUIRE(lua_gettop(L()) - top == nresults);
    lua_settop(L(), top);
    check_sentinel(L(), top);
    return "";
}

InterpreterState::InterpreterState() : L(luaL_newstate()) {
    luaL_openlibs(L);
    lua_pushcfunction(L, [](lua_State* S) {
        return scripting::open_gaitlab(S, scripting::StateOwner::interpreter);
    });
    scripting::protected_call(L, 0, 1);
    lua_setglobal(L, "gaitlab");
}

InterpreterState::~InterpreterState() {
    lua_close(L);
}

void InterpreterState::run(const std::string& code) {
    REQUIRE(luaL_loadbufferx(L, code.data(), code.size(), "=i", "t") == LUA_OK);
    scripting::protected_call(L, 0, 0);
}

}  // namespace gaitlab::test
