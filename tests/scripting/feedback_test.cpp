// Feedback from the joints into a Lua controller (self:joint_angle and friends): the
// adaptive_sine example slows a gait the servos cannot follow until they can.
#include <catch2/catch.hpp>

#include <string>

#include "lua_fixture.h"

using gaitlab::test::LuaFixture;

namespace {

// an 8-module snake driven by `ctl_expr`; runs `seconds` and keeps the widest swings
void run_snake(LuaFixture& lua, const std::string& ctl_expr, double seconds) {
    lua.run("EXAMPLES = '" GAITLAB_SOURCE_DIR "/examples'");
    lua.run(R"(
        Adaptive = gaitlab.controller.load(EXAMPLES .. "/controllers/adaptive_sine.lua")
        robot = gaitlab.robot.chain{ modules = 8 }
        world = gaitlab.world{ floor = { friction = 0.8 } }
        world:add(robot)
        ctl = robot:group("pitch"):drive()" +
            ctl_expr + R"()
        sim = gaitlab.simulation{ world = world }
        sim:run()" +
            std::to_string(seconds) +
            R"()
        -- the widest measured swing of joint 4 over the last second
        widest = 0
        for _ = 1, 100 do
          sim:step(10)
          widest = math.max(widest, math.abs(robot:joints()[4].angle))
        end
    )");
}

}  // namespace

TEST_CASE("the joint readings a Lua controller gets are the joints' measured state", "[feedback]") {
    LuaFixture lua;
    lua.run(R"(
        Probe = gaitlab.controller{ name = "probe", values = { "a", "v", "t" },
          step = function(self, dt)
            for m = 1, self.joints do
              self.a[m] = self:joint_angle(m)
              self.v[m] = self:joint_velocity(m)
              self.t[m] = self:joint_torque(m)
              self:set_angle(m, 30)
            end
          end }
        robot = gaitlab.robot.chain{ modules = 3 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group{ 2, 3 }:drive(Probe())
        sim = gaitlab.simulation{ world = world, control_every = 1 }
        sim:run(0.2)
    )");
    // control_every = 1: the step at tick k read the joints the previous tick left
    lua.run("j = robot:joints()  sim:step(1)  v = ctl:values()");
    for (int m = 1; m <= 2; ++m) {
        const std::string joint = "j[" + std::to_string(m + 1) + "]";
        const std::string i = "[" + std::to_string(m) + "]";
        CHECK(lua.number("v.a" + i) == Approx(lua.number(joint + ".angle")).margin(1e-9));
        CHECK(lua.number("v.v" + i) == Approx(lua.number(joint + ".velocity")).margin(1e-9));
        CHECK(lua.number("v.t" + i) == Approx(lua.number(joint + ".torque")).margin(1e-9));
    }
    CHECK(lua.number("v.a[1]") > 10);  // rising towards 30
    CHECK(lua.error_of(
              "gaitlab.controller{ name = 'x', values = { 'joint_angle' }, step = print }") ==
          "test:1: bad argument #1 to 'controller' (field 'values': 'joint_angle' is reserved (a "
          "method of every controller))");
    CHECK(lua.error_of("gaitlab.controller{ name = 'y', params = { set_angle = { 1, min = 0, "
                       "max = 2 } }, step = print }") ==
          "test:1: bad argument #1 to 'controller' (field 'params': 'set_angle' is reserved (a "
          "method of every controller))");
}

TEST_CASE("adaptive_sine slows a gait the servos cannot follow until the joints swing as asked",
          "[feedback]") {
    // a plain sine at 3 Hz leaves the joints far short of 60 degrees
    LuaFixture plain;
    run_snake(plain, "gaitlab.controllers.sine{ amplitude = 60, frequency = 3, phase = 120 }", 10);
    CHECK(plain.number("widest") < 20);

    LuaFixture lua;
    run_snake(lua, "Adaptive{ amplitude = 60, frequency = 3, phase = 120 }", 15);
    const double f = lua.number("ctl:values().running[1]");
    CAPTURE(f);
    // a first-order servo lag of 0.12 s allows 90% of the amplitude up to about 0.64 Hz
    CHECK(f > 0.45);
    CHECK(f < 0.7);
    CHECK(lua.number("widest") > 0.85 * 60);
    CHECK(lua.number("ctl.frequency") == 3);  // the parameter asked for is untouched

    // a gait the servos can follow keeps its frequency
    LuaFixture easy;
    run_snake(easy, "Adaptive{ amplitude = 40, frequency = 0.5, phase = 120 }", 10);
    CHECK(easy.number("ctl:values().running[1]") == 0.5);
}
