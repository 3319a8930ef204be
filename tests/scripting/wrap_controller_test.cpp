// gaitlab.controllers, gaitlab.controller{...} and controller handles
// (scripting/src/wrap_controller.cpp).
#include <catch2/catch.hpp>

#include <cmath>

#include "lua_fixture.h"

using gaitlab::test::lua_dir;
using gaitlab::test::LuaFixture;

TEST_CASE("parameters are range-checked at construction", "[wrap_controller]") {
    LuaFixture lua;
    const std::string bad = "test:1: bad argument #1 to 'sine' (";
    CHECK(lua.error_of("gaitlab.controllers.sine{ amplitude = 120 }") ==
          bad + "sine.amplitude must be in [0, 90] deg (got 120))");
    CHECK(lua.error_of("gaitlab.controllers.sine{ frequency = -1 }") ==
          bad + "sine.frequency must be in [0, 5] Hz (got -1))");
    CHECK(lua.error_of("gaitlab.controllers.sine{ phase = math.huge }") ==
          bad + "sine.phase must be in [-180, 180] deg (got inf))");
    CHECK(lua.error_of("gaitlab.controllers.sine{ amplitude = 'big' }") ==
          bad + "field 'amplitude': number expected, got string)");
    CHECK(lua.error_of("gaitlab.controllers.sine{ amplitud = 30 }") ==
          bad +
              "unknown key 'amplitud'; did you mean 'amplitude'? (parameters of 'sine': "
              "amplitude, frequency, phase, phase0, offset))");
    CHECK(lua.error_of("gaitlab.controllers.sine{ speed = 30 }") ==
          bad +
              "unknown key 'speed' (parameters of 'sine': amplitude, frequency, phase, phase0, "
              "offset))");
    CHECK(lua.error_of("gaitlab.controllers.sine{ 30 }") ==
          bad + "unexpected number key (fields are named))");
    CHECK(lua.error_of("gaitlab.controllers.sine(30)") == bad + "table expected, got number)");
}

TEST_CASE("parameters are range-checked online", "[wrap_controller]") {
    LuaFixture lua;
    lua.run("ctl = gaitlab.controllers.sine{ amplitude = 30 }");
    CHECK(lua.error_of("ctl.amplitude = 120") ==
          "test:1: sine.amplitude must be in [0, 90] deg (got 120)");
    CHECK(lua.number("ctl.amplitude") == 30);
    CHECK(lua.error_of("ctl.amplitude = 'big'") ==
          "test:1: sine.amplitude: number expected, got string");
    CHECK(lua.error_of("ctl.amplitud = 3") ==
          "test:1: controller 'sine' has no parameter 'amplitud'; did you mean 'amplitude'?");
    CHECK(lua.error_of("ctl.name = 'x'") == "test:1: controller 'sine' has no parameter 'name'");
    CHECK(lua.error_of("return ctl.amplitud") ==
          "test:1: controller 'sine' has no parameter or method 'amplitud'; did you mean "
          "'amplitude'?");
    CHECK(lua.error_of("ctl:parms()") ==
          "test:1: controller 'sine' has no parameter or method 'parms'; did you mean 'params'?");
    lua.run("ctl.amplitude = 90 ctl.offset = -90");
    CHECK(lua.number("ctl.amplitude") == 90);
    CHECK(lua.number("ctl.offset") == -90);
    CHECK(lua.string("ctl.name") == "sine");
    CHECK(lua.string("tostring(ctl)") == "gaitlab.Controller 'sine'");
}

TEST_CASE("params() describes every parameter", "[wrap_controller]") {
    LuaFixture lua;
    lua.run("p = gaitlab.controllers.sine{ amplitude = 30 }:params()");
    CHECK(lua.number("p.amplitude.value") == 30);
    CHECK(lua.number("p.amplitude.default") == 40);
    CHECK(lua.number("p.amplitude.min") == 0);
    CHECK(lua.number("p.amplitude.max") == 90);
    CHECK(lua.string("p.amplitude.unit") == "deg");
    CHECK(lua.string("p.frequency.unit") == "Hz");
    CHECK(lua.number("p.phase.min") == -180);
    CHECK(lua.number("p.phase.value") == 120);
    CHECK(lua.integer(
              "(function() local n = 0 for _ in pairs(p) do n = n + 1 end return n end)()") == 5);
}

TEST_CASE("values() holds per-joint arrays that advance with time", "[wrap_controller]") {
    LuaFixture lua;
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 4 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group{ 1, 2, 3 }:drive(gaitlab.controllers.sine{ amplitude = 30 })
        unbound = ctl:values()
        sim = gaitlab.simulation{ world = world }
        before = ctl:values()
        sim:run(0.3)
        after = ctl:values()
    )");
    // a controller has joints once a simulation binds it to its group
    CHECK(lua.integer("#unbound.time") == 0);
    CHECK(lua.integer("#before.time") == 3);
    CHECK(lua.number("before.time[1]") == 0);
    CHECK(lua.integer("#after.time") == 3);
    CHECK(lua.integer("#after.angle") == 3);
    // one control step every 30 ticks of 1 ms: each joint's clock reads a multiple of 0.03 s
    const double t = lua.number("after.time[1]");
    CHECK(t > 0.2);
    CHECK(t <= 0.3 + 1e-9);
    CHECK(std::fmod(t + 1e-9, 0.03) < 1e-8);
    CHECK(lua.number("after.time[3]") == t);
    CHECK(lua.number("after.angle[1]") == Approx(30 * std::sin(2 * 3.141592653589793 * 0.5 * t)));
}

TEST_CASE("changing a parameter online changes the targets", "[wrap_controller]") {
    LuaFixture lua;
    // frequency 0 and phase0 90 deg hold joint 1 at +amplitude; joint 2 at its offset
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        wave = gaitlab.controllers.sine{ amplitude = 20, frequency = 0, phase0 = 90 }
        robot:group{ 1 }:drive(wave)
        bias = robot:group{ 2 }:drive(gaitlab.controllers.sine{ amplitude = 0, offset = 10 })
        sim = gaitlab.simulation{ world = world }
        sim:run(0.1)
        a1, o1 = robot:joints()[1].target, robot:joints()[2].target
        wave.amplitude = 35
        bias.offset = -20
        sim:run(0.1)
        a2, o2 = robot:joints()[1].target, robot:joints()[2].target
    )");
    CHECK(lua.number("a1") == Approx(20));
    CHECK(lua.number("a2") == Approx(35));
    CHECK(lua.number("o1") == Approx(10));
    CHECK(lua.number("o2") == Approx(-20));
    CHECK(lua.number("wave:params().amplitude.value") == 35);
}

TEST_CASE("gaitlab.controller declares a class and a call makes an instance", "[wrap_controller]") {
    LuaFixture lua;
    lua.run(R"(
        Hold = gaitlab.controller{
          name = "hold",
          params = { level = { 5, min = -10, max = 10, unit = "deg" } },
          values = { "count" },
          step = function(self, dt) end,
        }
        a = Hold{}
        b = Hold{ level = -3 }
    )");
    CHECK(lua.string("Hold.name") == "hold");
    CHECK(lua.string("tostring(Hold)") == "gaitlab.ControllerClass 'hold'");
    CHECK(lua.number("a.level") == 5);
    CHECK(lua.number("b.level") == -3);
    CHECK(lua.string("a:params().level.unit") == "deg");
    CHECK(lua.error_of("Hold{ level = 11 }") ==
          "test:1: bad argument #1 to 'Hold' (hold.level must be in [-10, 10] deg (got 11))");
    CHECK(lua.error_of("Hold{ levl = 1 }") ==
          "test:1: bad argument #1 to 'Hold' (unknown key 'levl'; did you mean 'level'? "
          "(parameters of 'hold': level))");
    const std::string bad = "test:1: bad argument #1 to 'controller' (";
    CHECK(lua.error_of("gaitlab.controller{ step = function() end }") ==
          bad + "field 'name': string expected, got nil)");
    CHECK(lua.error_of("gaitlab.controller{ name = 'x', step = 3 }") ==
          bad + "field 'step': function expected, got number)");
    CHECK(lua.error_of("gaitlab.controller{ name = 'x', stp = function() end }") ==
          bad + "unknown key 'stp'; did you mean 'step'?)");
    CHECK(lua.error_of("gaitlab.controller{ name = 'x', params = { a = { 5, min = 0, max = 1 } }, "
                       "step = function() end }") ==
          bad + "parameter 'a' of controller 'x': default 5 is outside its range [0, 1])");
    CHECK(lua.error_of("gaitlab.controller{ name = 'x', params = { a = { min = 0, max = 1 } }, "
                       "step = function() end }") ==
          bad + "params.a: default value expected as the first entry)");
    CHECK(lua.error_of("gaitlab.controller{ name = 'x', params = { a = 3 }, "
                       "step = function() end }") ==
          bad + "params.a: table expected ({default, min = , max = , unit = }), got number)");
    CHECK(lua.error_of("gaitlab.controller{ name = 'x', values = { 'joints' }, "
                       "step = function() end }") ==
          bad + "field 'values': 'joints' is reserved (it holds the joint count))");
    // a parameter named as a field or method of the controller's handle would hide it: a
    // controller with a parameter 'failed' read ctl.failed == 0 after it failed
    for (const char* name : {"name", "failed", "error", "params", "values", "set"}) {
        INFO(name);
        CHECK(lua.error_of(std::string("gaitlab.controller{ name = 'x', params = { ") + name +
                           " = { 0, min = 0, max = 1 } }, step = function() end }") ==
              bad + "field 'params': '" + name + "' is reserved (the controller handle's ctl." +
                  name + " would be hidden by it))");
    }
}

TEST_CASE("one controller has one handle, whichever call gives it", "[wrap_controller][handles]") {
    LuaFixture lua;
    lua.run(R"(
        Hold = gaitlab.controller{ name = "hold", step = function(self, dt) end }
        robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
        sine = gaitlab.controllers.sine{}
        hold = Hold{}
        driven = robot:group("all"):drive(sine)
        robot:group{ 2 }:drive(hold)
        names = { [sine] = "sine", [hold] = "hold" }
        world = gaitlab.world()
        world:add(robot)
        sim = gaitlab.simulation{ world = world, record = false }
    )");
    CHECK(lua.boolean("rawequal(driven, sine)"));
    CHECK(lua.boolean("rawequal(robot:controllers()[1], sine)"));
    CHECK(lua.boolean("robot:controllers()[2] == hold"));
    CHECK(lua.boolean("sim:robot('snake'):controllers()[2] == hold"));
    CHECK(lua.string("names[robot:controllers()[1]]") == "sine");
    CHECK(lua.string("names[sim:robot('snake'):controllers()[2]]") == "hold");
    // two controllers of one kind and parameters are two controllers
    CHECK(lua.boolean("gaitlab.controllers.sine{} ~= gaitlab.controllers.sine{}"));
    CHECK(lua.boolean("Hold{} ~= hold and sine ~= hold"));
    CHECK(lua.boolean("sine ~= 'sine' and sine ~= Hold and hold ~= Hold and sine ~= robot"));
    // a class is one value too: instances are not it
    CHECK(
        lua.boolean("Hold == Hold and Hold ~= gaitlab.controller{ name = 'hold', "
                    "step = function() end }"));
    // the handle robot:controllers() gives knows its controller drives a group
    lua.run("robot, driven, sine, names = nil  collectgarbage()  collectgarbage()");
    CHECK_THAT(lua.error_of("gaitlab.robot.chain{ modules = 2 }:group('all'):drive("
                            "sim:robot('snake'):controllers()[1])"),
               Catch::Contains("controller 'sine' already drives a group"));
}

TEST_CASE("controller.load caches per file and resolves relative to the caller",
          "[wrap_controller]") {
    LuaFixture lua;
    lua.run("DIR = '" + lua_dir() + "'");
    lua.run(R"(
        A = gaitlab.controller.load(DIR .. "/counter.lua")
        B = gaitlab.controller.load(DIR .. "/sub/../counter.lua")
        C = dofile(DIR .. "/sub/loader.lua")
    )");
    CHECK(lua.string("A.name") == "counter");
    CHECK(lua.boolean("rawequal(A, B)"));
    CHECK(lua.boolean("rawequal(A, C)"));
    CHECK(lua.string("A.file") == lua_dir() + "/counter.lua");
    // instances of one class are independent
    lua.run("a, b = A{ level = 1 }, A{ level = 2 }");
    CHECK(lua.number("a.level") == 1);
    CHECK(lua.number("b.level") == 2);
}

TEST_CASE("controller.load reports files that are missing or wrong", "[wrap_controller]") {
    LuaFixture lua;
    const std::string dir = lua_dir();
    lua.run("DIR = '" + dir + "'");
    CHECK(lua.error_of("gaitlab.controller.load(DIR .. '/none.lua')") ==
          "test:1: cannot load controller '" + dir + "/none.lua': no file at " + dir + "/none.lua");
    CHECK(lua.error_of("gaitlab.controller.load(DIR .. '/no_return.lua')") ==
          "test:1: " + dir +
              "/no_return.lua: a controller file must return "
              "gaitlab.controller{...}, got nil");
    CHECK(lua.error_of("gaitlab.controller.load(42)") ==
          "test:1: bad argument #1 to 'load' (string expected, got number)");

    const auto e = lua.script_error_of("gaitlab.controller.load(DIR .. '/syntax_error.lua')");
    CHECK(std::string(e.what()) ==
          dir + "/syntax_error.lua:4: '}' expected (to close '{' at line 2) near 'step'");
    // a controller file that failed to load is not cached: a second load reports it again
    CHECK(e.file() == dir + "/syntax_error.lua");
    CHECK(lua.error_of("gaitlab.controller.load(DIR .. '/syntax_error.lua')") == e.what());
}
