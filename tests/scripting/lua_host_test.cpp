// The Lua host and its protected-call helper (scripting/src/lua_host.cpp).
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>

#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::scripting::LuaHost;
using gaitlab::scripting::ScriptError;
using gaitlab::test::lua_dir;
using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

TEST_CASE("syntax errors name the chunk and line", "[lua_host]") {
    LuaFixture lua;
    const ScriptError e = lua.script_error_of("local x = 1\nlocal y = = 2");
    CHECK(std::string(e.what()) == "test:2: unexpected symbol near '='");
    CHECK(e.file() == "=test");
    CHECK(e.line() == 0);

    LuaHost host;
    const std::string file = lua_dir() + "/syntax_error.lua";
    try {
        host.run_file(file);
        FAIL("no error");
    } catch (const ScriptError& err) {
        CHECK(std::string(err.what()) ==
              file + ":4: '}' expected (to close '{' at line 2) near 'step'");
        CHECK(err.file() == file);
    }
    CHECK(lua_gettop(host.state()) == 0);
}

TEST_CASE("a file too deep to read or compiled by luac is named, with what is wrong",
          "[lua_host]") {
    // "gaitlab: C stack overflow" named no file; a binary chunk said "mode is 't'"
    TempDir dir("lua_host_deep");
    const std::string deep = dir / "deep.lua";
    write_text(deep, "x = " + std::string(300, '(') + "1" + std::string(300, ')') + "\n");
    const std::string binary = dir / "compiled.lua";
    write_text(binary, std::string("\x1bLua\x54\x00 compiled", 16));
    for (const auto& [file, says] :
         {std::pair{deep,
                    ": C stack overflow (the code nests too deep to read: more than about "
                    "200 levels of parentheses"},
          std::pair{binary,
                    ": a compiled Lua chunk (luac's output): gaitlab reads Lua source "
                    "only"}}) {
        INFO(file);
        LuaHost host;
        try {
            host.run_file(file);
            FAIL("no error");
        } catch (const ScriptError& err) {
            CHECK_THAT(std::string(err.what()), Catch::StartsWith(file + says));
        }
    }
}

TEST_CASE("require finds modules beside the script only: a name cannot climb to the root",
          "[lua_host]") {
    // require ".tmp.x.evil" became the path "/tmp/x/evil.lua", absolute, and loaded it
    TempDir dir("lua_host_require_root");
    write_text(dir / "evil.lua", "return 'loaded from anywhere'");
    std::string name = dir / "evil";
    std::replace(name.begin(), name.end(), '/', '.');
    REQUIRE(name.find('.', 1) != std::string::npos);
    std::filesystem::create_directories(dir.path / "sub");
    write_text(dir / "sub/main.lua",
               "ok, got = pcall(require, '" + name + "')\nok2, got2 = pcall(require, '..evil')\n");
    LuaFixture lua;
    lua.host.run_file(dir / "sub/main.lua");
    CHECK_FALSE(lua.boolean("ok"));
    CHECK_THAT(lua.string("got"), Catch::Contains("(names are NAME or FOLDER.NAME)") &&
                                      !Catch::Contains("loaded from anywhere"));
    CHECK_FALSE(lua.boolean("ok2"));
}

TEST_CASE("a missing file is a ScriptError naming it", "[lua_host]") {
    LuaHost host;
    const std::string file = lua_dir() + "/none.lua";
    try {
        host.run_file(file);
        FAIL("no error");
    } catch (const ScriptError& e) {
        CHECK(std::string(e.what()) == "cannot read " + file + ": No such file or directory");
        CHECK(e.file() == file);
    }
    CHECK(lua_gettop(host.state()) == 0);
}

TEST_CASE("a script that is a directory, a FIFO or a device is refused, never read", "[lua_host]") {
    TempDir tmp("host_special");
    LuaHost host;
    CHECK_THROWS_WITH(host.run_file(tmp.str()), "cannot read " + tmp.str() + ": is a directory");
    const std::string fifo = tmp / "fifo.lua";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    CHECK_THROWS_WITH(host.run_file(fifo),
                      "cannot read " + fifo + ": not a regular file (a FIFO, device or socket)");
    const std::string zero = tmp / "zero.lua";
    std::filesystem::create_symlink("/dev/zero", zero);
    CHECK_THROWS_WITH(host.run_file(zero),
                      "cannot read " + zero + ": not a regular file (a FIFO, device or socket)");
    // a shebang line and a byte order mark are skipped, keeping line numbers
    write_text(tmp / "bom.lua", "\xEF\xBB\xBF#!/usr/bin/env gaitlab\nx = 1\nerror('here')\n");
    CHECK_THROWS_WITH(host.run_file(tmp / "bom.lua"), (tmp / "bom.lua") + ":3: here");
}

TEST_CASE("runtime errors carry file, line and traceback", "[lua_host]") {
    LuaFixture lua;
    const ScriptError e = lua.script_error_of(
        "local function inner() error('deep trouble') end\n"
        "local function outer() inner() end\n"
        "outer()");
    CHECK(std::string(e.what()) == "test:1: deep trouble");
    CHECK(e.file() == "test");
    CHECK(e.line() == 1);
    CHECK_THAT(e.traceback(), Catch::StartsWith("stack traceback:"));
    CHECK_THAT(e.traceback(), Catch::Contains("test:2: in "));
    CHECK_THAT(e.traceback(), Catch::Contains("test:3: in "));

    // error values that are not strings still give a message, with the place they came from
    CHECK(lua.error_of("error({})") == "test:1: (error object is a table value)");
    CHECK(
        lua.error_of("error(setmetatable({}, { __tostring = function() return 'custom' end }))") ==
        "test:1: custom");
    CHECK(lua.error_of("error('no position', 0)") == "no position");
    // binding errors raised from inside a Lua function are located at the call
    const ScriptError b = lua.script_error_of("local r\nr = gaitlab.robot.chain{ modules = 0 }");
    CHECK(b.file() == "test");
    CHECK(b.line() == 2);
}

TEST_CASE("protected_call leaves the stack as a call with nresults would", "[lua_host]") {
    LuaHost host;
    lua_State* L = host.state();
    lua_pushliteral(L, "below");
    luaL_loadstring(L, "local a, b = ... return a + b, a * b");
    lua_pushinteger(L, 3);
    lua_pushinteger(L, 4);
    gaitlab::scripting::protected_call(L, 2, 2);
    REQUIRE(lua_gettop(L) == 3);
    CHECK(lua_tointeger(L, 2) == 7);
    CHECK(lua_tointeger(L, 3) == 12);
    lua_settop(L, 1);

    luaL_loadstring(L, "error('x')");
    lua_pushinteger(L, 3);
    CHECK_THROWS_AS(gaitlab::scripting::protected_call(L, 1, 2), ScriptError);
    REQUIRE(lua_gettop(L) == 1);
    CHECK(std::string(lua_tostring(L, 1)) == "below");
}

TEST_CASE("binding functions called directly keep the stack balanced", "[lua_host]") {
    LuaFixture lua;
    lua.run(R"(
        r = gaitlab.robot.chain{ modules = 3 }
        w = gaitlab.world()
        c = gaitlab.controllers.sine{}
    )");
    // successful calls leave exactly their results
    CHECK(lua.pcall("gaitlab.robot.chain", "{ modules = 2 }", 1).empty());
    CHECK(lua.pcall("getmetatable(gaitlab.world).__call", "gaitlab.world, { floor = false }", 1)
              .empty());
    CHECK(lua.pcall("r.group", "r, 'pitch'", 1).empty());
    CHECK(lua.pcall("r.joints", "r", 1).empty());
    CHECK(lua.pcall("r.bodies", "r", 1).empty());
    CHECK(lua.pcall("w.box", "w, { size = { 1, 1, 1 } }", 1).empty());
    CHECK(lua.pcall("w.add", "w, r", 1).empty());
    CHECK(lua.pcall("r:group{ 1 }.drive", "r:group{ 1 }, c", 1).empty());
    CHECK(lua.pcall("c.params", "c", 1).empty());
    CHECK(lua.pcall("c.values", "c", 1).empty());
    CHECK(lua.pcall("gaitlab.controllers.sine", "{ amplitude = 3 }", 1).empty());
    lua.run("sim = gaitlab.simulation{ world = w }");
    CHECK(lua.pcall("sim.run", "sim, 0.05", 0).empty());
    CHECK(lua.pcall("sim.step", "sim, 3", 0).empty());
    CHECK(lua.pcall("sim.reset", "sim", 0).empty());
    CHECK(lua.pcall("r.position", "r", 1).empty());
    CHECK(lua.pcall("r.displacement", "r", 1).empty());
    CHECK(lua.pcall("gaitlab.controller.load", "'" + lua_dir() + "/counter.lua'", 1).empty());
    CHECK(lua.pcall("gaitlab.controller.load", "'" + lua_dir() + "/counter.lua'", 1).empty());
    // failing calls leave only the error message (the fixture checks the stack)
    CHECK_THAT(lua.pcall("gaitlab.robot.chain", "{ modules = 0 }", 1),
               Catch::EndsWith("(modules must be at least 1 (got 0))"));
    CHECK_THAT(lua.pcall("gaitlab.robot.chain", "", 1),
               Catch::EndsWith("(table expected, got no value)"));
    CHECK_THAT(lua.pcall("r.group", "r, { 9 }", 1),
               Catch::EndsWith("(robot 'robot' has no joint 9 (it has joints 1 to 3))"));
    CHECK_THAT(lua.pcall("sim.run", "sim, -1", 0),
               Catch::EndsWith("(non-negative number of seconds expected)"));
    CHECK_THAT(lua.pcall("gaitlab.controller.load", "'" + lua_dir() + "/syntax_error.lua'", 1),
               Catch::Contains("syntax_error.lua:4: '}' expected"));
    CHECK_THAT(lua.pcall("gaitlab.controller.load", "'" + lua_dir() + "/no_return.lua'", 1),
               Catch::EndsWith("no_return.lua: a controller file must return "
                               "gaitlab.controller{...}, got nil"));
    CHECK_THAT(lua.pcall("debug.getmetatable(c).__newindex", "c, 'amplitude', 120", 0),
               Catch::EndsWith("sine.amplitude must be in [0, 90] deg (got 120)"));
    CHECK_THAT(lua.pcall("debug.getmetatable(c).__index", "c, 'amplitud'", 1),
               Catch::Contains("has no parameter or method 'amplitud'"));
}

TEST_CASE("seed makes math.random reproducible", "[lua_host]") {
    auto draws = [](std::uint64_t seed) {
        LuaFixture lua;
        lua.host.seed(seed);
        lua.run("t = {} for i = 1, 5 do t[i] = math.random(1000000) end");
        return lua.string("table.concat(t, ' ')");
    };
    CHECK(draws(1) == draws(1));
    CHECK(draws(123456789) == draws(123456789));
    CHECK(draws(1) != draws(2));
}

TEST_CASE("set_args makes the arg table as lua.c does", "[lua_host]") {
    LuaFixture lua;
    lua.host.set_args("script.lua", {"one", "2", "--three"});
    CHECK(lua.string("arg[0]") == "script.lua");
    CHECK(lua.integer("#arg") == 3);
    CHECK(lua.string("arg[1]") == "one");
    CHECK(lua.string("arg[3]") == "--three");
    CHECK(lua.integer("select('#', table.unpack(arg))") == 3);
}

TEST_CASE("the gaitlab module is a global with a version", "[lua_host]") {
    LuaFixture lua;
    CHECK(lua.string("type(gaitlab)") == "table");
    CHECK_FALSE(lua.string("gaitlab.version").empty());
    CHECK(lua.boolean("package.loaded.gaitlab == gaitlab"));
}
