// gaitlab.robot: the chain builder, joint groups and robot measures (scripting/src/wrap_robot.cpp).
#include <catch2/catch.hpp>

#include <cmath>

#include "lua_fixture.h"

using gaitlab::test::LuaFixture;

namespace {

// a 4-module pitch-yaw snake in a world with a floor, not yet simulated
const char* kSnake = R"(
robot = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-yaw" }
world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
)";

}  // namespace

TEST_CASE("chain rejects bad arguments with Lua-worded messages", "[wrap_robot]") {
    LuaFixture lua;
    const std::string bad = "test:1: bad argument #1 to 'chain' (";
    CHECK(lua.error_of("gaitlab.robot.chain{modules = 0}") ==
          bad + "modules must be at least 1 (got 0))");
    CHECK(lua.error_of("gaitlab.robot.chain{modules = -3}") ==
          bad + "modules must be at least 1 (got -3))");
    CHECK(lua.error_of("gaitlab.robot.chain{modules = 1001}") ==
          bad + "modules must be at most 1000 (got 1001))");
    CHECK(lua.error_of("gaitlab.robot.chain{modules = 2.5}") ==
          bad + "field 'modules': integer expected, got a fractional number)");
    CHECK(lua.error_of("gaitlab.robot.chain{modules = 'eight'}") ==
          bad + "field 'modules': integer expected, got string)");
    CHECK(lua.error_of("gaitlab.robot.chain{name = 'x'}") ==
          bad + "field 'modules': number of modules expected, got nil)");
    CHECK(lua.error_of("gaitlab.robot.chain{modules = 2, name = 3}") ==
          bad + "field 'name': string expected, got number)");
    CHECK(lua.error_of("gaitlab.robot.chain{modules = 2, connection = 'pitch-roll'}") ==
          bad +
              "unknown connection type 'pitch-roll' (expected 'pitch-pitch', 'pitch-yaw' or "
              "'yaw-yaw'))");
    CHECK(lua.error_of("gaitlab.robot.chain{modules = 2, conection = 'pitch-yaw'}") ==
          bad + "unknown key 'conection'; did you mean 'connection'?)");
    CHECK(lua.error_of("gaitlab.robot.chain{modules = 2, colour = 'red'}") ==
          bad + "unknown key 'colour')");
    CHECK(lua.error_of("gaitlab.robot.chain{8, 'pitch-pitch'}") ==
          bad + "unexpected number key (fields are named))");
    CHECK(lua.error_of("gaitlab.robot.chain(8)") == bad + "table expected, got number)");
    CHECK(lua.error_of("gaitlab.robot.chain()") == bad + "table expected, got no value)");
}

TEST_CASE("groups must name joints the robot has", "[wrap_robot]") {
    LuaFixture lua;
    lua.run("r = gaitlab.robot.chain{ name = 'pp', modules = 3 }");
    const std::string bad = "test:1: bad argument #1 to 'group' (";
    CHECK(lua.error_of("r:group{1, 5}") ==
          bad + "robot 'pp' has no joint 5 (it has joints 1 to 3))");
    CHECK(lua.error_of("r:group{0}") == bad + "robot 'pp' has no joint 0 (it has joints 1 to 3))");
    CHECK(lua.error_of("r:group{}") == bad + "a joint group needs at least one joint)");
    CHECK(lua.error_of("r:group{1, 'two'}") == bad + "entry 2 is not a joint number)");
    CHECK(lua.error_of("r:group{2, 2}") == bad + "joint 2 is listed twice)");
    CHECK(lua.error_of("r:group('yaw')") == bad + "robot 'pp' has no yaw joints)");
    CHECK(lua.error_of("r:group('roll')") == bad + "robot 'pp' has no roll joints)");
    CHECK(lua.error_of("r:group('twist')") ==
          bad + "unknown joint role 'twist' (expected 'pitch', 'yaw', 'roll' or 'all'))");
    CHECK(lua.error_of("r:group(true)") ==
          bad +
              "role ('pitch', 'yaw', 'roll', 'all') or list of joint numbers "
              "expected, got boolean)");
    CHECK(lua.error_of("r.group(3, 'all')") ==
          "test:1: bad argument #1 to 'group' (gaitlab.Robot expected, got number)");
}

TEST_CASE("a controller drives one group only", "[wrap_robot]") {
    LuaFixture lua;
    lua.run("r = gaitlab.robot.chain{ modules = 3 } c = gaitlab.controllers.sine{}");
    lua.run("g = r:group{1, 2} same = g:drive(c) == c");
    CHECK(lua.boolean("same"));
    CHECK(lua.error_of("r:group{3}:drive(c)") ==
          "test:1: bad argument #1 to 'drive' (controller 'sine' already drives a group (create "
          "one controller per group))");
    CHECK(lua.error_of("r:group{3}:drive(42)") ==
          "test:1: bad argument #1 to 'drive' (gaitlab.Controller expected, got number)");
    CHECK(lua.integer("#g") == 2);
    CHECK(lua.string("table.concat(g:joints(), ',')") == "1,2");
}

TEST_CASE("a group is driven once, groups that partly overlap add up", "[wrap_robot]") {
    LuaFixture lua;
    lua.run(R"(
        r = gaitlab.robot.chain{ name = "snake", modules = 5, connection = "pitch-yaw" }
        wave = r:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 20 })
        bias = gaitlab.controllers.offset{ angle = 10 }
    )");
    const std::string twice =
        "test:1: controller 'offset' cannot drive joints 1, 3, 5 of robot 'snake': controller "
        "'sine' already drives exactly these joints (one controller per group: their targets "
        "would add up; groups that only partly overlap do add)";
    // the same role, or the same joints listed in another order
    CHECK(lua.error_of("r:group('pitch'):drive(bias)") == twice);
    CHECK(lua.error_of("r:group{5, 3, 1}:drive(bias)") == twice);
    // the refused controller is still free: it drives another group, partly overlapping
    lua.run("r:group('all'):drive(bias)");
    CHECK(lua.error_of("r:group{1, 2, 3, 4, 5}:drive(gaitlab.controllers.sine{})") ==
          "test:1: controller 'sine' cannot drive joints 1, 2, 3, 4, 5 of robot 'snake': "
          "controller 'offset' already drives exactly these joints (one controller per group: "
          "their targets would add up; groups that only partly overlap do add)");
    CHECK(lua.integer("#r:actuation():groups()") == 2);
    // while the simulation runs too; a subset of a group is a group of its own
    lua.run(R"(
        world = gaitlab.world()
        world:add(r)
        sim = gaitlab.simulation{ world = world }
        sim:run(0.1)
    )");
    CHECK(lua.error_of("r:group{1, 3, 5}:drive(gaitlab.controllers.offset{})") ==
          "test:1: controller 'offset' cannot drive joints 1, 3, 5 of robot 'snake': controller "
          "'sine' already drives exactly these joints (one controller per group: their targets "
          "would add up; groups that only partly overlap do add)");
    lua.run("r:group{3}:drive(gaitlab.controllers.offset{ angle = 5 }) sim:run(0.1)");
    CHECK(lua.error_of("r:group{3}:drive(gaitlab.controllers.offset{})") ==
          "test:1: controller 'offset' cannot drive joint 3 of robot 'snake': controller "
          "'offset' already drives exactly this joint (one controller per group: their targets "
          "would add up; groups that only partly overlap do add)");
    CHECK(lua.integer("#r:actuation():groups()") == 3);
}

TEST_CASE("groups select joints by role in order from the tail", "[wrap_robot]") {
    LuaFixture lua;
    lua.run("r = gaitlab.robot.chain{ modules = 5, connection = 'pitch-yaw' }");
    CHECK(lua.string("table.concat(r:group('pitch'):joints(), ',')") == "1,3,5");
    CHECK(lua.string("table.concat(r:group('yaw'):joints(), ',')") == "2,4");
    CHECK(lua.string("table.concat(r:group('all'):joints(), ',')") == "1,2,3,4,5");
    CHECK(lua.string("table.concat(r:group{5, 1, 3}:joints(), ',')") == "5,1,3");
}

TEST_CASE("robot measures need a simulation", "[wrap_robot]") {
    LuaFixture lua;
    lua.run(kSnake);
    const std::string not_in_sim =
        "test:1: robot 'snake' is not in a simulation yet (its world is built into one by "
        "gaitlab.simulation{world = ...})";
    CHECK(lua.error_of("robot:position()") == not_in_sim);
    // a robot in no world is told to go into one
    CHECK(lua.error_of("gaitlab.robot.chain{ name = 'alone', modules = 2 }:position()") ==
          "test:1: robot 'alone' is not in a simulation (add it to a world, then create "
          "gaitlab.simulation{world = ...})");
    CHECK(lua.error_of("robot:velocity()") == not_in_sim);
    CHECK(lua.error_of("robot:displacement()") == not_in_sim);
    // the spec part of bodies and joints is there before any simulation
    CHECK(lua.integer("#robot:bodies()") == 5);
    CHECK(lua.boolean("robot:bodies()[1].position == nil"));
    CHECK(lua.string("robot:joints()[2].role") == "yaw");
    CHECK(lua.boolean("robot:joints()[2].angle == nil"));
    // one whose simulation nothing holds any more is told so
    lua.run(
        "do local s = gaitlab.simulation{ world = world } end collectgarbage() collectgarbage()");
    CHECK(lua.error_of("robot:position()") ==
          "test:1: robot 'snake' is in no simulation now: the newest simulation built from its "
          "world is gone (nothing held it); create another: gaitlab.simulation{world = ...}");
}

TEST_CASE("robot handle: name, length, tostring", "[wrap_robot]") {
    LuaFixture lua;
    lua.run(kSnake);
    CHECK(lua.string("robot.name") == "snake");
    CHECK(lua.integer("#robot") == 4);
    CHECK(lua.string("tostring(robot)") == "gaitlab.Robot 'snake' (4 joints)");
    CHECK(lua.string("tostring(gaitlab.robot.chain{ modules = 1 })") ==
          "gaitlab.Robot 'robot' (1 joint)");
    lua.run(R"(
        one = gaitlab.robot.chain{ modules = 2 }
        one:group("all"):drive(gaitlab.controllers.sine{})
    )");
    CHECK(lua.string("tostring(one:actuation())") == "gaitlab.Actuation (1 group)");
    CHECK(lua.string("gaitlab.robot.chain{modules = 1}.name") == "robot");
    CHECK(lua.boolean("robot.no_such_member == nil"));
}

TEST_CASE("one robot has one handle: == and table keys", "[wrap_robot][handles]") {
    LuaFixture lua;
    lua.run(kSnake);
    lua.run(R"(
        other = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-yaw" }
        world:add(other)
        seen = { [robot] = "first" }
        sim = gaitlab.simulation{ world = world, record = false }
    )");
    // the chain's handle is the handle the simulation gives for its robot: the same userdata
    CHECK(lua.boolean("rawequal(sim:robot('snake'), robot)"));
    CHECK(lua.boolean("sim:robot('snake') == robot"));
    CHECK(lua.boolean("rawequal(sim:robot('snake_2'), sim:robot('snake_2'))"));
    CHECK(lua.string("seen[sim:robot('snake')]") == "first");
    // another robot, even of the same name and build, is another handle
    CHECK(lua.boolean("robot ~= other"));
    CHECK(lua.boolean("sim:robot('snake_2') == other"));
    CHECK(lua.boolean("seen[other] == nil"));
    // anything that is no robot handle is not equal, and comparing raises nothing
    lua.run(R"(
        for _, v in ipairs({ 1, "snake", {}, true, print, robot:group("all"),
                             gaitlab.modules.y1, sim, world, robot:actuation() }) do
          assert(robot ~= v and v ~= robot, tostring(v))
        end
        assert(robot ~= nil and nil ~= robot)
    )");
}

TEST_CASE("one group of joints has one handle: == and table keys", "[wrap_robot][handles]") {
    LuaFixture lua;
    lua.run(kSnake);  // pitch-yaw: pitch joints 1 and 3
    lua.run("g = robot:group('pitch')  t = { [g] = 'pitch' }");
    CHECK(lua.boolean("rawequal(robot:group('pitch'), g)"));
    CHECK(lua.string("t[robot:group('pitch')]") == "pitch");
    // the same joints, named by number: the same group
    CHECK(lua.boolean("robot:group{ 1, 3 } == g"));
    // other joints, the same joints in another order (which joint is the controller's first),
    // or another robot's joints: other groups
    CHECK(lua.boolean("robot:group('yaw') ~= g"));
    CHECK(lua.boolean("robot:group{ 3, 1 } ~= g"));
    CHECK(lua.boolean("robot:group{ 1 } ~= g"));
    CHECK(
        lua.boolean("gaitlab.robot.chain{ modules = 4, connection = 'pitch-yaw' }:group('pitch')"
                    " ~= g"));
    CHECK(lua.boolean("g ~= 'pitch' and g ~= robot and g ~= 1"));
    lua.run("c = gaitlab.controllers.sine{}  g:drive(c)");
    CHECK(lua.boolean("rawequal(robot:group{ 1, 3 }, g)"));
}

TEST_CASE("bodies lists tail, segments and head with poses", "[wrap_robot]") {
    LuaFixture lua;
    lua.run(kSnake);
    lua.run("sim = gaitlab.simulation{ world = world } bodies = robot:bodies()");
    CHECK(lua.integer("#bodies") == 5);
    CHECK(lua.string("bodies[1].name") == "tail");
    CHECK(lua.string("bodies[2].name") == "segment1");
    CHECK(lua.string("bodies[4].name") == "segment3");
    CHECK(lua.string("bodies[5].name") == "head");
    CHECK(lua.number("bodies[1].mass") == Approx(0.025));
    CHECK(lua.number("bodies[2].mass") == Approx(0.050));
    CHECK(lua.number("bodies[2].size.x") == Approx(0.072));
    CHECK(lua.number("bodies[2].size.y") == Approx(0.052));
    // laid along +x with the tail at the origin, resting on the floor
    CHECK(lua.number("bodies[1].position.x") == Approx(0.018).margin(1e-6));
    CHECK(lua.number("bodies[3].position.x") == Approx(0.144).margin(1e-6));
    CHECK(lua.number("bodies[5].position.x") == Approx(0.270).margin(1e-6));
    CHECK(lua.number("bodies[5].position.z") == Approx(0.026).margin(1e-6));
    CHECK(lua.number("bodies[1].orientation.w") == Approx(1).margin(1e-9));
    CHECK(lua.string("getmetatable(bodies[1].position).__name") == "gaitlab.Vec3");
    CHECK(lua.boolean("bodies[1].velocity ~= nil"));
    // the centre of mass is at the middle of the straight chain
    CHECK(lua.number("robot:position().x") == Approx(0.144).margin(1e-6));
    CHECK(lua.number("robot:displacement():norm()") == Approx(0).margin(1e-12));
    lua.run("sim:run(0.5)");
    CHECK(lua.number("robot:bodies()[1].position.z") == Approx(0.026).margin(2e-3));
}

TEST_CASE("joints lists angle, target, velocity in degrees and torque", "[wrap_robot]") {
    LuaFixture lua;
    lua.run(kSnake);
    lua.run(R"(
        robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 20, frequency = 1 })
        sim = gaitlab.simulation{ world = world }
        sim:run(0.3)
        joints = robot:joints()
    )");
    CHECK(lua.integer("#joints") == 4);
    CHECK(lua.integer("joints[3].index") == 3);
    CHECK(lua.string("joints[1].name") == "joint1");
    CHECK(lua.string("joints[1].role") == "pitch");
    CHECK(lua.string("joints[2].role") == "yaw");
    CHECK(lua.number("joints[1].min") == Approx(-90));
    CHECK(lua.number("joints[1].max") == Approx(90));
    for (const char* field : {"angle", "target", "velocity", "torque"}) {
        CHECK(lua.string(std::string("type(joints[1].") + field + ")") == "number");
    }
    // the sine's target for joint 1 at its last control tick (t = 0.3 s): 20 sin(2π·0.3) deg
    CHECK(lua.number("joints[1].target") == Approx(20 * std::sin(2 * 3.14159265358979 * 0.3)));
    // the yaw joints are not driven: their target is 0
    CHECK(lua.number("joints[2].target") == 0);
    // the servo follows its target: the measured angle is on the way (degrees, not radians)
    CHECK(lua.number("joints[1].angle") > 5);
    CHECK(lua.number("math.abs(joints[1].torque)") <= 0.4 + 1e-9);
}

TEST_CASE("robot names are valid UTF-8 without control characters", "[wrap_robot][names]") {
    LuaFixture lua;
    CHECK(lua.error_of("gaitlab.robot.chain{ name = 'snake\\n', modules = 2 }") ==
          "test:1: bad argument #1 to 'chain' (robot name must be valid UTF-8 without control "
          "characters (got \"snake\\x0a\"))");
    CHECK(lua.error_of("gaitlab.robot.chain{ name = 'bad\\xff', modules = 2 }") ==
          "test:1: bad argument #1 to 'chain' (robot name must be valid UTF-8 without control "
          "characters (got \"bad\\xff\"))");
    CHECK(lua.error_of("gaitlab.robot.chain{ name = string.rep('a', 300), modules = 2 }") ==
          "test:1: bad argument #1 to 'chain' (robot name must be at most 256 bytes long (got "
          "300 bytes))");
    lua.run("r = gaitlab.robot.chain{ name = 'serpent à sonnettes / 2', modules = 2 }");
    CHECK(lua.string("r.name") == "serpent à sonnettes / 2");
}

TEST_CASE("robot:energy() is the servos' work, as the recording and the fitness read it",
          "[wrap_robot]") {
    LuaFixture lua;
    lua.run(kSnake);
    lua.run(R"(
        robot:group("all"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 1 })
        idle = gaitlab.robot.chain{ name = "idle", modules = 2 }
        world:add(idle, { y = 1 })
    )");
    CHECK(lua.error_of("robot:energy()") ==
          "test:1: robot 'snake' is not in a simulation yet (its world is built into one by "
          "gaitlab.simulation{world = ...})");
    CHECK(lua.number("robot:joints()[1].energy or -1") == -1);  // state fields only in a sim
    lua.run("sim = gaitlab.simulation{ world = world }");
    CHECK(lua.number("robot:energy()") == 0);
    // |torque x velocity| summed by hand over every physics step
    lua.run(R"(
        by_hand = 0
        for _ = 1, 500 do
          sim:step(1)
          for _, j in ipairs(robot:joints()) do
            by_hand = by_hand + math.abs(j.torque * math.rad(j.velocity)) * sim.dt
          end
        end
        sum = 0
        for _, j in ipairs(robot:joints()) do sum = sum + j.energy end
    )");
    const double energy = lua.number("robot:energy()");
    INFO("energy " << energy << " J");
    CHECK(energy > 0);
    CHECK(energy == Approx(lua.number("by_hand")).epsilon(1e-9));
    CHECK(energy == lua.number("sum"));  // the sum over the joints, in joint order
    CHECK(energy == lua.number("sim:status().robots[1].energy"));
    // the undriven robot holds its pose: next to no work
    CHECK(lua.number("idle:energy()") < 1e-3 * energy);
    CHECK(lua.number("sim:status().robots[2].energy") == lua.number("idle:energy()"));
    // a clone carries it on; a reset sets it to 0
    CHECK(lua.number("sim:clone():robot('snake'):energy()") == energy);
    lua.run("sim:reset()");
    CHECK(lua.number("robot:energy()") == 0);
}

TEST_CASE("robot:heading() and robot:turned() measure a turn", "[wrap_robot]") {
    LuaFixture lua;
    lua.run(R"(
        straight = gaitlab.robot.chain{ modules = 4 }
        robot = gaitlab.robot.chain{ name = "turner", modules = 4, connection = "pitch-yaw" }
        world = gaitlab.world{ floor = { friction = 0.8 } }
        world:add(straight, { y = 1 })
        world:add(robot, { yaw = 170 })
        robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5,
                                                             phase = 120 })
        -- a constant bend of the yaw joints turns it counter-clockwise
        robot:group("yaw"):drive(gaitlab.controllers.sine{ amplitude = 0, offset = -20 })
    )");
    CHECK(lua.error_of("straight:heading()") ==
          "test:1: robot 'robot' is not in a simulation yet (its world is built into one by "
          "gaitlab.simulation{world = ...})");
    lua.run("sim = gaitlab.simulation{ world = world }");
    CHECK(lua.number("straight:heading()") == Approx(0).margin(1e-5));
    CHECK(lua.number("robot:heading()") == Approx(170).margin(1e-5));
    CHECK(lua.number("robot:turned()") == 0);
    lua.run("sim:run(24)");
    // past +180 the heading wraps to -180 and on; the turn goes on counting
    const double heading = lua.number("robot:heading()");
    const double turned = lua.number("robot:turned()");
    CHECK(heading < -160);
    CHECK(turned > 15);
    CHECK(turned < 40);
    CHECK(std::remainder(170 + turned - heading, 360) == Approx(0).margin(1e-5));
    CHECK(lua.number("straight:heading()") == Approx(0).margin(0.05));  // lying still
    CHECK(lua.number("sim:status().robots[2].turned") == Approx(turned));
    lua.run("sim:reset()");
    CHECK(lua.number("robot:heading()") == Approx(170).margin(1e-5));
    CHECK(lua.number("robot:turned()") == 0);
    CHECK(lua.error_of("robot.heading()") ==
          "test:1: bad argument #1 to 'heading' (gaitlab.Robot expected, got no value)");
}
