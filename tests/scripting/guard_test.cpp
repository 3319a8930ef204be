// The limits Lua code runs under (scripting/src/guard.cpp): budgets that pcall, xpcall and
// coroutines cannot escape, budgets on controller files and their hooks, interrupts from
// another thread, the memory limit of a host, the debug hooks of others given back, and
// Ctrl-C in the state of an interpreter that required gaitlab.
#include <signal.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "guard.h"
#include "lua_fixture.h"
#include "temp_dir.h"
#include "wrap.h"

using gaitlab::scripting::LuaHost;
using gaitlab::scripting::ScriptError;
using gaitlab::test::InterpreterState;
using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

// a 2-module chain whose first joint the controller class `cls` (a Lua expression) drives,
// in a simulation `sim` that stops at the first failure
void drive(LuaFixture& lua, const std::string& cls) {
    lua.run(
        "robot = gaitlab.robot.chain{ modules = 2 }\n"
        "world = gaitlab.world()\n"
        "world:add(robot)\n"
        "ctl = robot:group{ 1 }:drive((" +
        cls +
        ")())\n"
        "sim = gaitlab.simulation{ world = world }\n");
}

// runs `fn` and checks it ends within a few seconds
template <class F>
void quickly(F&& fn) {
    const auto start = std::chrono::steady_clock::now();
    fn();
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(10));
}

}  // namespace

TEST_CASE("pcall and xpcall cannot swallow a spent budget", "[guard]") {
    const char* bodies[] = {
        // the review's example
        "while true do pcall(function() while true do end end) end",
        // a message handler that loops, inside a loop of xpcalls
        "while true do xpcall(function() while true do end end, function() while true do end "
        "end) end",
        // errors turned into values, then retried forever
        "local n = 0 while true do local ok = pcall(error, 'x') n = n + 1 end",
        // string.gsub calling back into a loop that swallows
        "while true do pcall(string.gsub, ('x'):rep(100), '.', function() while true do end "
        "end) end",
    };
    for (const char* body : bodies) {
        CAPTURE(body);
        LuaFixture lua;
        drive(lua, std::string("gaitlab.controller{ name = 'spin', instruction_budget = 100000, "
                               "step = function(self, dt) ") +
                       body + " end }");
        quickly([&] {
            const auto e = lua.script_error_of("sim:run(1)");
            CHECK_THAT(std::string(e.what()),
                       Catch::StartsWith("controller 'spin' exceeded its instruction budget of "
                                         "100000 instructions in one step (test:"));
        });
        CHECK(lua.boolean("ctl.failed"));
        CHECK(lua.boolean("debug.gethook() == nil"));          // nothing left behind
        lua.run("x = 0 for i = 1, 1000000 do x = x + i end");  // the script runs freely again
    }
}

TEST_CASE("pairs' sort, done in C, is charged to the budget", "[guard]") {
    // each pairs call sorts the table's 200 000 keys in C, where the hook counts nothing: 200
    // calls took 4 s of CPU within the default budget of 10 million instructions, and the loop
    // around them 600 instructions
    LuaFixture lua;
    lua.run("big = {} for i = 1, 200000 do big['k' .. i] = i end");
    drive(lua,
          "gaitlab.controller{ name = 'sorter', step = function() for i = 1, 200 do "
          "for k in pairs(big) do break end end end }");
    quickly([&] {
        CHECK_THAT(lua.error_of("sim:run(1)"),
                   Catch::StartsWith("controller 'sorter' exceeded its instruction budget of "
                                     "10000000 instructions in one step (test:"));
    });
    CHECK(lua.boolean("ctl.failed"));
    // outside a budget pairs is as free as before, and a step sorting small tables is fine
    lua.run("n = 0 for k in pairs(big) do n = n + 1 end");
    CHECK(lua.integer("n") == 200000);
    LuaFixture small;
    small.run("t = { a = 1, b = 2, c = 3 }");
    drive(small,
          "gaitlab.controller{ name = 'ok', instruction_budget = 100000, step = function() for "
          "i = 1, 100 do for k in pairs(t) do end end end }");
    small.run("sim:run(1)");
    CHECK_FALSE(small.boolean("ctl.failed"));
}

TEST_CASE("coroutines run under the budget of the code that resumes them", "[guard]") {
    LuaFixture lua;
    // made outside any budget, resumed by a step: the loop inside must still stop
    lua.run(R"(
        forever = coroutine.create(function() while true do end end)
        wrapped = coroutine.wrap(function() while true do coroutine.yield(1) end end)
    )");
    drive(lua,
          "gaitlab.controller{ name = 'co', instruction_budget = 100000, "
          "step = function() wrapped() while true do coroutine.resume(forever) end end }");
    quickly([&] {
        CHECK_THAT(lua.error_of("sim:run(1)"),
                   Catch::Contains("controller 'co' exceeded its instruction budget"));
    });
    // coroutine.wrap raises errors with their position, as the standard one does
    CHECK(lua.error_of("coroutine.wrap(function() error('boom') end)()") ==
          "test:1: test:1: boom");  // as lua5.4 says it
    lua.run("w = coroutine.wrap(function(a, b) local c = coroutine.yield(a + b) return c * 2 end)");
    CHECK(lua.integer("w(1, 2)") == 3);
    CHECK(lua.integer("w(5)") == 10);
    CHECK_THAT(lua.error_of("coroutine.resume(42)"), Catch::Contains("thread expected"));
    // xpcall still lets its function yield, and still calls its handler for ordinary errors
    lua.run(
        "y = coroutine.wrap(function() xpcall(function() coroutine.yield(1) end, print) "
        "return 5 end)");
    CHECK(lua.integer("y()") == 1);
    CHECK(lua.integer("y()") == 5);
    CHECK(lua.string("select(2, xpcall(error, function(m) return 'handled ' .. m end, 'e'))") ==
          "handled e");
}

TEST_CASE("controller files, snapshot and on_reload run under a budget", "[guard]") {
    TempDir tmp("guard_files");
    LuaFixture lua;
    std::vector<std::string> reports;
    lua.host.set_reporter([&](const std::string& m) { reports.push_back(m); });
    const std::string file = tmp / "c.lua";
    // the top level of a file: first load
    write_text(file, "while true do pcall(function() while true do end end) end");
    quickly([&] {
        CHECK(lua.error_of("gaitlab.controller.load('" + file + "')") ==
              "controller file " + file +
                  " exceeded its instruction budget of 100000000 instructions while it loaded (" +
                  file + ":1)");
    });
    // a good version, with hooks that loop forever
    write_text(file, R"(return gaitlab.controller{ name = "c", values = { "time" },
  step = function(self, dt) self:set_angle(1, 10) end,
  snapshot = function(self) while true do end end,
  on_reload = function(self, s) while true do end end })");
    lua.run("C = gaitlab.controller.load('" + file + "')");
    drive(lua, "C");
    lua.run("sim:run(0.1)");
    // reload(): the old code's snapshot runs away; the reload fails, the old version runs on
    quickly([&] {
        lua.run("ok, err = gaitlab.controller.reload()");
        CHECK_FALSE(lua.boolean("ok"));
        CHECK_THAT(lua.string("err"),
                   Catch::Contains("controller 'c' exceeded its instruction budget of 100000000 "
                                   "instructions in snapshot"));
    });
    lua.run("sim:run(0.1)");
    CHECK_FALSE(lua.boolean("ctl.failed"));
    // a new version whose on_reload runs away: it fails at the next step
    const std::string file2 = tmp / "d.lua";
    write_text(file2, R"(return gaitlab.controller{ name = "d",
  step = function(self, dt) self:set_angle(1, 10) end })");
    lua.run("D = gaitlab.controller.load('" + file2 + "')");
    drive(lua, "D");
    write_text(file2, R"(return gaitlab.controller{ name = "d",
  step = function(self, dt) self:set_angle(1, 10) end,
  on_reload = function(self, s) while true do end end })");
    lua.run("gaitlab.controller.reload()");  // c.lua's snapshot still fails; d.lua reloads
    CHECK(lua.integer("D.version") == 1);
    quickly([&] {
        CHECK_THAT(lua.error_of("sim:run(0.1)"), Catch::Contains("instructions in on_reload"));
    });
    // a save during a run: the file is reloaded between ticks, under the same budget
    const std::string file3 = tmp / "e.lua";
    write_text(file3, "return gaitlab.controller{ name = 'e', step = function() end }");
    lua.run("E = gaitlab.controller.load('" + file3 + "')");
    drive(lua, "E");
    lua.host.set_reload_interval(0);
    reports.clear();
    write_text(file3, "while true do end");
    quickly([&] { lua.run("sim:run(0.2)"); });
    REQUIRE_FALSE(reports.empty());
    CHECK_THAT(reports[0], Catch::Contains("exceeded its instruction budget of 100000000 "
                                           "instructions while it loaded"));
}

TEST_CASE("an interrupt stops a script at its next instruction, even inside pcall", "[guard]") {
    for (const char* code :
         {"while true do pcall(function() while true do end end) end",
          "local co = coroutine.wrap(function() while true do end end) co()",
          // a simulation stepping in C++ stops between ticks
          "local r = gaitlab.robot.chain{ modules = 2 } local w = gaitlab.world() w:add(r) "
          "local s = gaitlab.simulation{ world = w } while true do pcall(s.run, s, 1e6) end"}) {
        CAPTURE(code);
        LuaHost host;
        std::thread stopper([&] {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            host.interrupt(SIGINT);
        });
        quickly([&] { CHECK_THROWS_WITH(host.run_string(code, "=x"), "interrupted (SIGINT)"); });
        stopper.join();
        CHECK(host.interrupted() == SIGINT);
        // until cleared, nothing runs; then the host works as before
        CHECK_THROWS_WITH(host.run_string("y = 1", "=x"), "interrupted (SIGINT)");
        host.clear_interrupt();
        CHECK(host.interrupted() == 0);
        host.run_string("y = 2", "=x");
        lua_getglobal(host.state(), "y");
        CHECK(lua_tointeger(host.state(), -1) == 2);
        lua_pop(host.state(), 1);
    }
}

TEST_CASE("a host's Lua state has a memory limit", "[guard]") {
    LuaHost host(64 << 20);
    // one huge string, then a table that grows without end: both fail as Lua errors
    CHECK_THROWS_WITH(host.run_string("local s = string.rep('x', 1 << 30)", "=m"),
                      "not enough memory");
    CHECK_THROWS_WITH(host.run_string("local t = {} for i = 1, 1e9 do t[i] = {} end", "=m"),
                      "not enough memory");
    // the state still works afterwards
    host.run_string("collectgarbage() ok = #string.rep('x', 1000)", "=m");
    lua_getglobal(host.state(), "ok");
    CHECK(lua_tointeger(host.state(), -1) == 1000);
    lua_pop(host.state(), 1);
}

TEST_CASE("a budget gives back the debug hook it found", "[guard]") {
    LuaFixture lua;
    lua.run("calls = 0 function counter() calls = calls + 1 end debug.sethook(counter, '', 1000)");
    drive(lua, "gaitlab.controller{ name = 'c', step = function() for i = 1, 1000 do end end }");
    lua.run("sim:run(0.1)");
    // the script's hook is back after every step, with its mask and count
    CHECK(lua.boolean("debug.gethook() == counter"));
    CHECK(lua.string("(select(2, debug.gethook()))") == "");
    CHECK(lua.integer("(select(3, debug.gethook()))") == 1000);
    // a budget still holds while it is away
    lua.run("cls = gaitlab.controller{ name = 'loop', step = function() while true do end end }");
    drive(lua, "cls");
    CHECK_THAT(lua.error_of("sim:run(0.1)"),
               Catch::Contains("controller 'loop' exceeded its instruction budget"));
    CHECK(lua.boolean("debug.gethook() == counter"));
}

namespace {

void (*sigint_handler())(int) {
    struct sigaction sa {};
    sigaction(SIGINT, nullptr, &sa);
    return sa.sa_handler;
}

}  // namespace

TEST_CASE("Ctrl-C in an interpreter stops sim:run, then the interpreter has its handler back",
          "[guard]") {
    InterpreterState lua;
    // the interpreter's own SIGINT handler (lua.c has one while it runs a script) and hook
    struct sigaction own {};
    own.sa_handler = [](int) {};
    sigemptyset(&own.sa_mask);
    struct sigaction before {};
    sigaction(SIGINT, &own, &before);
    lua.run("function counter() end debug.sethook(counter, '', 1000000)");
    lua.run(
        "robot = gaitlab.robot.chain{ modules = 2 } world = gaitlab.world() world:add(robot) "
        "robot:group{ 1 }:drive(gaitlab.controller{ name = 'c', step = function(self) "
        "self:set_angle(1, 5) end }()) sim = gaitlab.simulation{ world = world }");
    std::thread stopper([] {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        kill(getpid(), SIGINT);
    });
    quickly([&] {
        lua.run("ok, err = pcall(sim.run, sim, 3600)");  // minutes, if nothing stopped it
    });
    stopper.join();
    lua_getglobal(lua.L, "err");
    CHECK_THAT(std::string(luaL_optstring(lua.L, -1, "")), Catch::Contains("interrupted (SIGINT)"));
    lua_pop(lua.L, 1);
    // the error went to the script, which goes on: no interrupt left, the script's hook and the
    // interpreter's handler are back
    lua.run("after = sim.time sim:run(0.01) assert(sim.time > after)");
    lua.run("assert(debug.gethook() == counter)");
    CHECK(sigint_handler() == own.sa_handler);
    // a state gaitlab owns leaves signals to its host
    LuaFixture host;
    drive(host, "gaitlab.controller{ name = 'c', step = function() end }");
    host.run("sim:run(0.01)");
    CHECK(sigint_handler() == own.sa_handler);
    sigaction(SIGINT, &before, nullptr);
}
