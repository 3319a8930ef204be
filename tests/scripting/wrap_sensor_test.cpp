// Sensors from Lua (scripting/src/wrap_sensor.cpp): robot:sensor{...}, robot:sensor(name),
// robot:sensors(), sensor handles, their switches and readings in degrees, and exact errors.
#include <catch2/catch.hpp>

#include <cmath>

#include "lua_fixture.h"

using gaitlab::test::LuaFixture;

namespace {

// a 4-module pitch-pitch snake in a world with a floor, not yet simulated
const char* kSnake = R"(
robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
)";

}  // namespace

TEST_CASE("robot:sensor rejects bad sensors before anything runs", "[wrap_sensor]") {
    LuaFixture lua;
    lua.run(kSnake);
    const std::string bad = "test:1: bad argument #1 to 'sensor' (";
    CHECK(lua.error_of("robot:sensor{ kind = 'imu', module = 5 }") ==
          bad + "robot 'snake' has no module 5 (it has modules 1 to 4))");
    CHECK(lua.error_of("robot:sensor{ kind = 'contact', module = 0 }") ==
          bad + "robot 'snake' has no module 0 (it has modules 1 to 4))");
    CHECK(lua.error_of("robot:sensor{ kind = 'joint', joint = 7 }") ==
          bad + "robot 'snake' has no joint 7 (it has joints 1 to 4))");
    CHECK(lua.error_of("robot:sensor{ kind = 'imy', module = 1 }") ==
          bad +
              "unknown sensor kind 'imy'; did you mean 'imu'? (expected 'joint', 'imu', "
              "'contact', 'range' or 'position'))");
    CHECK(lua.error_of("robot:sensor{ kind = 'sonar', module = 1 }") ==
          bad +
              "unknown sensor kind 'sonar' (expected 'joint', 'imu', 'contact', 'range' or "
              "'position'))");
    CHECK(lua.error_of("robot:sensor{ module = 1 }") ==
          bad +
              "field 'kind': sensor kind expected ('joint', 'imu', 'contact', 'range' or "
              "'position'), got nil)");
    CHECK(lua.error_of("robot:sensor{ kind = 'imu', modul = 1 }") ==
          bad + "unknown key 'modul'; did you mean 'module'?)");
    CHECK(lua.error_of("robot:sensor{ kind = 'range', module = 1, max_rang = 1 }") ==
          bad + "unknown key 'max_rang'; did you mean 'max_range'?)");
    CHECK(lua.error_of("robot:sensor{ kind = 'imu', module = 1, colour = 'red' }") ==
          bad + "unknown key 'colour')");
    CHECK(lua.error_of("robot:sensor{ kind = 'contact', module = 1, half = 'tail' }") ==
          bad +
              "key 'half' does not apply to contact sensors (their keys: kind, name, module, "
              "enabled))");
    CHECK(lua.error_of("robot:sensor{ kind = 'joint', module = 1 }") ==
          bad +
              "key 'module' does not apply to joint sensors (their keys: kind, name, joint, "
              "enabled))");
    CHECK(lua.error_of("robot:sensor{ kind = 'imu', module = 1, max_range = 2 }") ==
          bad +
              "key 'max_range' does not apply to imu sensors (their keys: kind, name, module, "
              "half, enabled))");
    CHECK(lua.error_of("robot:sensor{ kind = 'imu' }") ==
          bad + "field 'module': module number expected, got nil)");
    CHECK(lua.error_of("robot:sensor{ kind = 'joint' }") ==
          bad + "field 'joint': joint number expected, got nil)");
    CHECK(lua.error_of("robot:sensor{ kind = 'imu', module = 1.5 }") ==
          bad + "field 'module': integer expected, got a fractional number)");
    CHECK(lua.error_of("robot:sensor{ kind = 'imu', module = 1, half = 'haed' }") ==
          bad +
              "field 'half': unknown module half 'haed'; did you mean 'head'? (expected 'tail' "
              "or 'head'))");
    CHECK(lua.error_of("robot:sensor{ kind = 'range', module = 1, max_range = 200 }") ==
          bad + "sensor 'range1' max_range must be in [0.01, 100] m (got 200))");
    CHECK(lua.error_of("robot:sensor{ kind = 'range', module = 1, max_range = 0 }") ==
          bad + "sensor 'range1' max_range must be in [0.01, 100] m (got 0))");
    CHECK(lua.error_of("robot:sensor{ kind = 'range', module = 1, direction = {0, 0, 0} }") ==
          bad + "sensor 'range1' direction must be a non-zero vector)");
    CHECK(lua.error_of("robot:sensor{ kind = 'range', module = 1, direction = 'down' }") ==
          bad + "field 'direction': vector expected ({x, y, z}), got string)");
    CHECK(lua.error_of("robot:sensor{ kind = 'imu', module = 1, enabled = 1 }") ==
          bad + "field 'enabled': boolean expected, got number)");
    CHECK(lua.error_of("robot:sensor{ kind = 'imu', module = 1, name = 'my imu' }") ==
          bad + "sensor name 'my imu' may contain only letters, digits and '_')");
    CHECK(lua.error_of("robot:sensor(42)") ==
          bad + "sensor table or sensor name expected, got number)");
    CHECK(lua.error_of("robot.sensor(world, {})") ==
          "test:1: bad argument #1 to 'sensor' (gaitlab.Robot expected, got gaitlab.World)");
    // nothing was attached by the failed calls
    CHECK(lua.integer("#robot:sensors()") == 0);

    lua.run("robot:sensor{ kind = 'imu', module = 3 }");
    CHECK(lua.error_of("robot:sensor{ kind = 'imu', module = 3 }") ==
          bad + "robot 'snake' already has a sensor named 'imu3' (give this one another name))");
    CHECK(lua.error_of("robot:sensor('imu4')") ==
          bad + "robot 'snake' has no sensor 'imu4'; did you mean 'imu3'? (its sensors: imu3))");
    CHECK(lua.error_of("gaitlab.robot.chain{ name = 'r', modules = 1 }:sensor('x')") ==
          bad + "robot 'r' has no sensor 'x' (it has no sensors))");
}

TEST_CASE("sensor handles describe their sensor", "[wrap_sensor]") {
    LuaFixture lua;
    lua.run(kSnake);
    lua.run(R"(
        imu = robot:sensor{ kind = "imu", module = 2, half = "tail" }
        ray = robot:sensor{ kind = "range", name = "nose", module = 4, direction = {1, 0, 0.5},
                            max_range = 1.5, enabled = false }
        js = robot:sensor{ kind = "joint", joint = 1 }
        pos = robot:sensor{ kind = "position" }
    )");
    CHECK(lua.string("imu.name") == "imu2");
    CHECK(lua.string("imu.kind") == "imu");
    CHECK(lua.integer("imu.module") == 2);
    CHECK(lua.string("imu.half") == "tail");
    CHECK(lua.boolean("imu.joint == nil and imu.max_range == nil and imu.direction == nil"));
    CHECK(lua.boolean("imu.enabled"));
    CHECK(lua.string("ray.name") == "nose");
    CHECK(lua.string("ray.half") == "head");
    CHECK(lua.number("ray.max_range") == 1.5);
    CHECK(lua.number("ray.direction.z") == 0.5);
    CHECK_FALSE(lua.boolean("ray.enabled"));
    CHECK(lua.integer("js.joint") == 1);
    CHECK(lua.boolean("js.module == nil and js.half == nil"));
    CHECK(lua.boolean("pos.module == nil and pos.joint == nil"));
    CHECK(lua.string("tostring(imu)") == "gaitlab.Sensor 'imu2' (imu on module 2 (tail half), on)");
    CHECK(lua.string("tostring(ray)") ==
          "gaitlab.Sensor 'nose' (range on module 4 (head half), off)");
    CHECK(lua.string("tostring(js)") == "gaitlab.Sensor 'joint1' (joint on joint 1, on)");
    CHECK(lua.string("tostring(pos)") == "gaitlab.Sensor 'position' (position, on)");
    CHECK(lua.string("robot:sensor('nose').name") == "nose");
    CHECK(lua.integer("#robot:sensors()") == 4);
    CHECK(lua.string("robot:sensors()[4].name") == "position");

    // channels with user units
    lua.run(R"(
        local parts = {}
        for _, c in ipairs(imu:channels()) do parts[#parts + 1] = c.name .. " " .. c.unit end
        imu_channels = table.concat(parts, ", ")
        parts = {}
        for _, c in ipairs(gaitlab.sensor.channels("range")) do
          parts[#parts + 1] = c.name .. " " .. c.unit
        end
        range_channels = table.concat(parts, ", ")
    )");
    CHECK(lua.string("imu_channels") ==
          "roll deg, pitch deg, yaw deg, qw , qx , qy , qz , wx deg/s, wy deg/s, wz deg/s, "
          "ax m/s², ay m/s², az m/s²");
    CHECK(lua.string("range_channels") == "distance m, hit boolean");
    CHECK(lua.string("table.concat(gaitlab.sensor.kinds, ' ')") ==
          "joint imu contact range position");
    CHECK(lua.error_of("gaitlab.sensor.channels('gps')") ==
          "test:1: bad argument #1 to 'channels' (unknown sensor kind 'gps' (expected 'joint', "
          "'imu', 'contact', 'range' or 'position'))");

    // fields: only the switch can change
    CHECK(lua.error_of("imu.enabld = false") ==
          "test:1: sensor 'imu2' has no field 'enabld'; did you mean 'enabled'?");
    CHECK(lua.error_of("imu.module = 3") ==
          "test:1: sensor 'imu2': 'module' cannot be changed (only 'enabled' can)");
    CHECK(lua.error_of("imu.enabled = 'no'") ==
          "test:1: sensor 'imu2': enabled must be a boolean, got string");
    CHECK(lua.error_of("return imu.nmae") ==
          "test:1: sensor 'imu2' has no field or method 'nmae'; did you mean 'name'?");
    lua.run("imu.enabled = false");
    CHECK(lua.string("tostring(imu)") ==
          "gaitlab.Sensor 'imu2' (imu on module 2 (tail half), off)");

    // readings need a simulation
    CHECK(lua.error_of("imu:read()") ==
          "test:1: robot 'snake' is not in a simulation yet (its world is built into one by "
          "gaitlab.simulation{world = ...})");
}

TEST_CASE("one sensor has one handle: == and table keys", "[wrap_sensor][handles]") {
    LuaFixture lua;
    lua.run(kSnake);
    lua.run(R"(
        imu = robot:sensor{ kind = "imu", module = 2 }
        js = robot:sensor{ kind = "joint", joint = 1 }
        what = { [imu] = "tilt", [js] = "angle" }
    )");
    CHECK(lua.boolean("rawequal(robot:sensor('imu2'), imu)"));
    CHECK(lua.boolean("robot:sensors()[1] == imu and robot:sensors()[2] == js"));
    CHECK(lua.string("what[robot:sensor('joint1')]") == "angle");
    CHECK(lua.boolean("imu ~= js"));
    // the same kind on the same place of another robot is another sensor
    lua.run(R"(
        twin = gaitlab.robot.chain{ name = "snake", modules = 4 }
        twin_imu = twin:sensor{ kind = "imu", module = 2 }
    )");
    CHECK(lua.boolean("twin_imu ~= imu and what[twin_imu] == nil"));
    CHECK(lua.boolean("imu ~= 'imu2' and imu ~= robot and imu ~= 2 and imu ~= {}"));
    // the robot's handle from its simulation gives the same sensors, and a sensor attached
    // while it runs is one handle from then on
    lua.run(R"(
        sim = gaitlab.simulation{ world = world, record = false }
        sim:run(0.01)
        contact = sim:robot("snake"):sensor{ kind = "contact", module = 1 }
    )");
    CHECK(lua.boolean("rawequal(sim:robot('snake'):sensor('imu2'), imu)"));
    CHECK(lua.boolean("robot:sensor('contact1') == contact and robot:sensors()[3] == contact"));
    lua.run("sim:reset()");
    CHECK(lua.boolean("sim:robot('snake'):sensors()[1] == imu"));
    CHECK(lua.string("what[sim:robot('snake'):sensor('joint1')]") == "angle");
}

TEST_CASE("sensors read in degrees and SI units, booleans for on/off", "[wrap_sensor]") {
    LuaFixture lua;
    lua.run(kSnake);
    lua.run(R"(
        imu = robot:sensor{ kind = "imu", module = 4 }
        js = robot:sensor{ kind = "joint", joint = 4 }
        touch = robot:sensor{ kind = "contact", module = 4 }
        down = robot:sensor{ kind = "range", module = 2, direction = {0, 0, -1} }
        pos = robot:sensor{ kind = "position" }
        robot:group{4}:drive(gaitlab.controllers.offset{ angle = 30 })
        sim = gaitlab.simulation{ world = world }
        sim:run(1.5)
        r = imu:read()
        j = js:read()
        joint4 = robot:joints()[4]
        p = pos:read()
        c = robot:position()
        v = robot:velocity()
    )");
    // the head half of module 4, lifted by its joint held at 30 degrees
    CHECK(lua.number("j.angle") == Approx(30).margin(0.5));
    CHECK(lua.number("r.pitch") == Approx(lua.number("j.angle")).margin(0.2));
    CHECK(std::abs(lua.number("r.roll")) < 0.1);
    CHECK(lua.number("r.az") == Approx(9.81 * std::cos(30 * 3.14159265358979 / 180)).margin(0.05));
    // the joint sensor is the joint state, in degrees
    CHECK(lua.number("j.angle") == lua.number("joint4.angle"));
    CHECK(lua.number("j.velocity") == lua.number("joint4.velocity"));
    CHECK(lua.number("j.torque") == lua.number("joint4.torque"));
    // module 4 still has its tail half on the floor
    CHECK(lua.boolean("touch:read().contact == true"));
    CHECK(lua.number("touch:read().force") > 0);
    CHECK(lua.number("down:read().distance") == Approx(0.026).margin(5e-4));
    CHECK(lua.boolean("down:read().hit == true"));
    // the position sensor is robot:position() and robot:velocity()
    for (const char* k : {"x", "y", "z"}) {
        CHECK(lua.number(std::string("p.") + k) == lua.number(std::string("c.") + k));
        CHECK(lua.number(std::string("p.v") + k) == lua.number(std::string("v.") + k));
    }
}

TEST_CASE("switching a sensor off stops its readings, on resumes them", "[wrap_sensor]") {
    LuaFixture lua;
    lua.run(kSnake);
    lua.run(R"(
        js = robot:sensor{ kind = "joint", joint = 2 }
        robot:group("all"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 1 })
        sim = gaitlab.simulation{ world = world }
        sim:run(0.3)
        a = js:read().angle
        same = js:off() == js
    )");
    CHECK(lua.boolean("same"));
    CHECK(lua.boolean("js:read() == nil"));
    CHECK_FALSE(lua.boolean("js.enabled"));
    lua.run("sim:run(0.2) js.enabled = true");
    CHECK(lua.number("js:read().angle") == lua.number("robot:joints()[2].angle"));
    CHECK(lua.number("js:read().angle") != lua.number("a"));
    lua.run("sim:run(0.2)");
    CHECK(lua.number("js:read().angle") == lua.number("robot:joints()[2].angle"));
    // the switch survives a reset
    lua.run("js:off() sim:reset()");
    CHECK(lua.boolean("js:read() == nil"));
    lua.run("js:on()");
    CHECK(lua.number("js:read().angle") == lua.number("robot:joints()[2].angle"));
}

TEST_CASE("sensors can be attached while the simulation runs", "[wrap_sensor]") {
    LuaFixture lua;
    lua.run(kSnake);
    lua.run(R"(
        sim = gaitlab.simulation{ world = world }
        sim:run(0.2)
        imu = robot:sensor{ kind = "imu", module = 1, half = "tail" }
        az = imu:read().az
        sim:run(0.2)
    )");
    CHECK(lua.number("az") == Approx(9.81).margin(0.01));
    CHECK(lua.number("imu:read().az") == Approx(9.81).margin(0.01));
    CHECK(lua.string("robot:sensors()[1].name") == "imu1");
}

TEST_CASE("sensor module and joint numbers never wrap", "[wrap_sensor][limits]") {
    LuaFixture lua;
    lua.run("r = gaitlab.robot.chain{ name = 'snake', modules = 3 }");
    const std::string bad = "test:1: bad argument #1 to 'sensor' (";
    // 2^32 + 1 used to become module 1: numbers beyond an int are refused as they are
    CHECK(lua.error_of("r:sensor{ kind = 'imu', module = 2^32 + 1 }") ==
          bad + "field 'module': module number out of range, got 4294967297)");
    CHECK(lua.error_of("r:sensor{ kind = 'joint', joint = -2^40 }") ==
          bad + "field 'joint': joint number out of range, got -1099511627776)");
    CHECK(lua.error_of("r:sensor{ kind = 'imu', module = 1e19 }") ==
          bad + "field 'module': module number out of range, got 1e+19)");
    CHECK(lua.error_of("r:sensor{ kind = 'contact', module = -1e300 }") ==
          bad + "field 'module': module number out of range, got -1e+300)");
    CHECK(lua.error_of("r:sensor{ kind = 'joint', joint = math.mininteger }") ==
          bad + "field 'joint': joint number out of range, got -9223372036854775808)");
    // one below an int's lowest would wrap as the 0-based index: refused here too
    CHECK(lua.error_of("r:sensor{ kind = 'imu', module = -2^31 }") ==
          bad + "field 'module': module number out of range, got -2147483648)");
    // the numbers an int holds go to the robot's own check, which names its range
    CHECK(lua.error_of("r:sensor{ kind = 'imu', module = 2^31 - 1 }") ==
          bad + "robot 'snake' has no module 2147483647 (it has modules 1 to 3))");
    CHECK(lua.error_of("r:sensor{ kind = 'joint', joint = -2^31 + 1 }") ==
          bad + "robot 'snake' has no joint -2147483647 (it has joints 1 to 3))");
    CHECK(lua.error_of("r:sensor{ kind = 'imu', module = 2^31 }") ==
          bad + "field 'module': module number out of range, got 2147483648)");
}

TEST_CASE("a sensor's module or joint number must be a whole number", "[wrap_sensor]") {
    LuaFixture lua;
    lua.run("r = gaitlab.robot.chain{ name = 'snake', modules = 3 }");
    const std::string bad = "test:1: bad argument #1 to 'sensor' (";
    CHECK(lua.error_of("r:sensor{ kind = 'imu' }") ==
          bad + "field 'module': module number expected, got nil)");
    // a numeric string is not taken for its number
    CHECK(lua.error_of("r:sensor{ kind = 'imu', module = '3' }") ==
          bad + "field 'module': module number expected, got string)");
    CHECK(lua.error_of("r:sensor{ kind = 'joint', joint = true }") ==
          bad + "field 'joint': joint number expected, got boolean)");
    CHECK(lua.error_of("r:sensor{ kind = 'joint', joint = {} }") ==
          bad + "field 'joint': joint number expected, got table)");
    CHECK(lua.error_of("r:sensor{ kind = 'imu', module = 2.5 }") ==
          bad + "field 'module': integer expected, got a fractional number)");
    CHECK(lua.error_of("r:sensor{ kind = 'imu', module = 1/0 }") ==
          bad + "field 'module': integer expected, got inf)");
    // a whole float is its integer
    lua.run("s = r:sensor{ kind = 'imu', module = 3.0 }");
    CHECK(lua.string("s.name") == "imu3");
    CHECK(lua.number("#r:sensors()") == 1);
}

TEST_CASE("a sensor on a module or joint the robot does not have names the robot's range",
          "[wrap_sensor]") {
    LuaFixture lua;
    lua.run("r = gaitlab.robot.chain{ name = 'snake', modules = 4 }");
    const std::string bad = "test:1: bad argument #1 to 'sensor' (";
    // negative numbers used to reach the default name ("imu-1") and fail on its characters
    for (const char* kind : {"imu", "contact", "range"}) {
        CAPTURE(kind);
        const std::string k = kind;
        CHECK(lua.error_of("r:sensor{ kind = '" + k + "', module = -1 }") ==
              bad + "robot 'snake' has no module -1 (it has modules 1 to 4))");
        CHECK(lua.error_of("r:sensor{ kind = '" + k + "', module = 2^62 }") ==
              bad + "field 'module': module number out of range, got 4611686018427387904)");
        CHECK(lua.error_of("r:sensor{ kind = '" + k + "', module = 0/0 }") ==
              bad + "field 'module': integer expected, got nan)");
        CHECK(lua.error_of("r:sensor{ kind = '" + k + "', module = -1/0 }") ==
              bad + "field 'module': integer expected, got -inf)");
    }
    CHECK(lua.error_of("r:sensor{ kind = 'joint', joint = -1 }") ==
          bad + "robot 'snake' has no joint -1 (it has joints 1 to 4))");
    CHECK(lua.error_of("r:sensor{ kind = 'joint', joint = 0/0 }") ==
          bad + "field 'joint': integer expected, got nan)");
    // a robot without joints has no modules at all
    lua.run(
        "b = gaitlab.robot.new{ name = 'brick', bodies = { { name = 'b', size = {0.1, 0.1, "
        "0.1}, mass = 1 } } }");
    CHECK(lua.error_of("b:sensor{ kind = 'imu', module = 1 }") ==
          bad + "robot 'brick' has no modules)");
    CHECK(lua.error_of("b:sensor{ kind = 'joint', joint = 1 }") ==
          bad + "robot 'brick' has no joints)");
    // nothing was attached
    CHECK(lua.number("#r:sensors()") == 0);
}
