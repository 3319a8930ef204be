// A Lua controller that fails while a simulation runs: the on_controller_error option ("stop"
// raises from sim:run, "continue" marks it failed, holds its joints and reports once), ctl.failed
// and ctl.error, and the instruction budget that stops a runaway step.
#include <catch2/catch.hpp>

#include <chrono>
#include <string>
#include <vector>

#include "lua_fixture.h"

using gaitlab::test::LuaFixture;

namespace {

// a 4-module snake whose pitch joints a Lua controller drives; it fails on its 10th step
// (t = 0.27 s), at line 6 of the chunk "test"
const char* kFailingSnake = R"(
        Wobble = gaitlab.controller{ name = "wobble",
          step = function(self, dt)
            self.n = (self.n or 0) + 1
            for m = 1, self.joints do self:set_angle(m, 30 * math.sin(self.n / 3 + m)) end
            if self.n == 10 then error("wobble broke") end
          end }
        robot = gaitlab.robot.chain{ modules = 4 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group("pitch"):drive(Wobble())
)";

}  // namespace

TEST_CASE("on_controller_error = 'stop' raises from sim:run and marks the controller failed",
          "[controller_failure]") {
    LuaFixture lua;
    lua.run(kFailingSnake);
    lua.run("sim = gaitlab.simulation{ world = world }");
    CHECK(lua.string("sim.on_controller_error") == "stop");
    CHECK(lua.boolean("ctl.failed") == false);
    CHECK(lua.boolean("ctl.error == nil"));
    const auto e = lua.script_error_of("sim:run(1)");
    CHECK(std::string(e.what()) == "test:6: wobble broke");
    CHECK(e.file() == "test");
    CHECK(e.line() == 6);
    CHECK(lua.boolean("ctl.failed"));
    CHECK(lua.string("ctl.error") == "test:6: wobble broke");
    CHECK(lua.number("sim.time") == Approx(0.27));
}

TEST_CASE("an error Lua raises without a place is placed at the step's line",
          "[controller_failure]") {
    // "attempt to yield from outside a coroutine" named no file, line or controller
    LuaFixture lua;
    lua.run(R"(
        Yielder = gaitlab.controller{ name = "yielder",
          step = function(self, dt)
            coroutine.yield()
          end }
        robot = gaitlab.robot.chain{ modules = 3 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group("pitch"):drive(Yielder())
        sim = gaitlab.simulation{ world = world, on_controller_error = "continue" }
        sim:run(0.1)
    )");
    CHECK(lua.boolean("ctl.failed"));
    CHECK(lua.string("ctl.error") == "test:4: attempt to yield from outside a coroutine");
}

TEST_CASE("on_controller_error = 'continue' holds the failed group and keeps running",
          "[controller_failure]") {
    LuaFixture lua;
    std::vector<std::string> reports;
    lua.host.set_reporter([&](const std::string& m) { reports.push_back(m); });
    lua.run(kFailingSnake);
    lua.run(R"(
        sim = gaitlab.simulation{ world = world, on_controller_error = "continue" }
        sim:run(0.3)
        held = {}
        for j, s in ipairs(robot:joints()) do held[j] = s.target end
        sim:run(2)
        after = robot:joints()
    )");
    CHECK(lua.string("sim.on_controller_error") == "continue");
    CHECK(lua.number("sim.time") == Approx(2.3));
    CHECK(lua.boolean("ctl.failed"));
    CHECK(lua.string("ctl.error") == "test:6: wobble broke");
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].rfind("controller 'wobble' failed: test:6: wobble broke\nstack traceback:",
                           0) == 0);
    CHECK(reports[0].find("test:6: in ") != std::string::npos);
    for (int j = 1; j <= 3; ++j) {
        const std::string held = "held[" + std::to_string(j) + "]";
        // targets frozen at the angles measured at the failure; the joints stay there
        CHECK(lua.number("after[" + std::to_string(j) + "].target") == lua.number(held));
        CHECK(lua.number("after[" + std::to_string(j) + "].angle") ==
              Approx(lua.number(held)).margin(3));
    }
    // reset runs it again
    lua.run("sim:reset()");
    CHECK(lua.boolean("ctl.failed") == false);
    CHECK(lua.error_of("gaitlab.simulation{ world = world, on_controller_error = 'halt' }") ==
          "test:1: bad argument #1 to 'simulation' (field 'on_controller_error': 'stop', "
          "'continue' or 'pause' expected, got 'halt')");
}

TEST_CASE("on_controller_error = 'pause' returns from sim:run at the failure, and runs on after",
          "[controller_failure]") {
    LuaFixture lua;
    std::vector<std::string> reports;
    lua.host.set_reporter([&](const std::string& m) { reports.push_back(m); });
    lua.run(kFailingSnake);
    lua.run(R"(
        sim = gaitlab.simulation{ world = world, on_controller_error = "pause" }
        sim:run(5)
    )");
    CHECK(lua.string("sim.on_controller_error") == "pause");
    CHECK(lua.boolean("sim.paused"));
    // the 10th control step is at tick 270; the tick completes, then the run returns
    CHECK(lua.integer("sim.ticks") == 271);
    CHECK(lua.boolean("ctl.failed"));
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].rfind("controller 'wobble' failed: test:6: wobble broke", 0) == 0);
    // running again goes on with the failed group holding, and is not paused again
    lua.run("sim:run(1)");
    CHECK(lua.boolean("sim.paused") == false);
    CHECK(lua.integer("sim.ticks") == 1271);
    CHECK(reports.size() == 1);
}

TEST_CASE("the instruction budget stops a runaway step", "[controller_failure]") {
    LuaFixture lua;
    std::vector<std::string> reports;
    lua.host.set_reporter([&](const std::string& m) { reports.push_back(m); });
    lua.run(R"(
        Spin = gaitlab.controller{ name = "spin", instruction_budget = 100000,
          step = function(self, dt)
            while true do end
          end }
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group{ 1 }:drive(Spin())
        sim = gaitlab.simulation{ world = world }
    )");
    CHECK(lua.integer("Spin.instruction_budget") == 100000);
    const auto e = lua.script_error_of("sim:run(1)");
    CHECK(std::string(e.what()) ==
          "controller 'spin' exceeded its instruction budget of 100000 instructions in one step "
          "(test:4)");
    CHECK(e.file() == "test");
    CHECK(e.line() == 4);
    CHECK(lua.boolean("ctl.failed"));
    CHECK(lua.boolean("debug.gethook() == nil"));  // the hook is only set while a step runs

    // the default budget is generous, and stops a runaway too
    lua.run(R"(
        Loop = gaitlab.controller{ name = "loop", step = function() while true do end end }
        robot2 = gaitlab.robot.chain{ modules = 2 }
        world2 = gaitlab.world()
        world2:add(robot2)
        loop = robot2:group{ 1 }:drive(Loop())
        sim2 = gaitlab.simulation{ world = world2, on_controller_error = "continue" }
    )");
    CHECK(lua.integer("Loop.instruction_budget") == 10000000);
    const auto start = std::chrono::steady_clock::now();
    lua.run("sim2:run(0.1)");
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
    CHECK(lua.string("loop.error") ==
          "controller 'loop' exceeded its instruction budget of 10000000 instructions in one "
          "step (test:2)");
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].rfind("controller 'loop' failed: controller 'loop' exceeded", 0) == 0);
    CHECK(lua.error_of("gaitlab.controller{ name = 'x', step = print, instruction_budget = 0 }") ==
          "test:1: bad argument #1 to 'controller' (field 'instruction_budget': integer in [1, "
          "2147483647] expected)");
}
