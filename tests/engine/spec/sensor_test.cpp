// Tests for engine/src/spec/sensor.cpp: kinds, default names, channels and units, and the checks of
// sensor specs (exact messages).
#include "gaitlab/sensor.h"

#include <catch2/catch.hpp>

#include <limits>

#include "gaitlab/error.h"
#include "gaitlab/robot.h"
#include "gaitlab/simulation.h"
#include "gaitlab/world.h"

using namespace gaitlab;
using Catch::Matchers::Equals;

namespace {

RobotSpec snake(int modules = 4) {
    ChainSpec c;
    c.name = "snake";
    c.modules = modules;
    return make_chain(c);
}

SensorSpec of_kind(SensorKind kind, int index = 0) {
    SensorSpec s;
    s.kind = kind;
    s.module = index;
    s.joint = index;
    return s;
}

}  // namespace

TEST_CASE("sensor kinds and halves have names") {
    CHECK(sensor_kind_names() ==
          std::vector<std::string>{"joint", "imu", "contact", "range", "position"});
    for (const std::string& n : sensor_kind_names())
        CHECK(to_string(parse_sensor_kind(n)) == n);
    REQUIRE_THROWS_AS(parse_sensor_kind("imy"), SpecError);
    REQUIRE_THROWS_WITH(parse_sensor_kind("imy"),
                        Equals("unknown sensor kind 'imy' (expected 'joint', 'imu', 'contact', "
                               "'range' or 'position')"));
    CHECK(parse_module_half("tail") == ModuleHalf::tail);
    CHECK(to_string(parse_module_half("head")) == std::string("head"));
    REQUIRE_THROWS_WITH(parse_module_half("middle"),
                        Equals("unknown module half 'middle' (expected 'tail' or 'head')"));
}

TEST_CASE("sensors are named after their kind and the number users give them") {
    CHECK(default_sensor_name(of_kind(SensorKind::joint, 2)) == "joint3");
    CHECK(default_sensor_name(of_kind(SensorKind::imu, 0)) == "imu1");
    CHECK(default_sensor_name(of_kind(SensorKind::contact, 7)) == "contact8");
    CHECK(default_sensor_name(of_kind(SensorKind::range, 3)) == "range4");
    CHECK(default_sensor_name(of_kind(SensorKind::position)) == "position");
    SensorSpec s = of_kind(SensorKind::imu, 1);
    CHECK(sensor_name(s) == "imu2");
    s.name = "nose";
    CHECK(sensor_name(s) == "nose");
}

TEST_CASE("each kind reports named channels in engine units") {
    auto names = [](SensorKind k) {
        std::vector<std::string> out;
        for (const SensorChannel& c : sensor_channels(k))
            out.push_back(c.name + " " + c.unit + (c.boolean ? " bool" : ""));
        return out;
    };
    CHECK(names(SensorKind::joint) ==
          std::vector<std::string>{"angle rad", "velocity rad/s", "torque N·m"});
    CHECK(names(SensorKind::imu) == std::vector<std::string>{"roll rad", "pitch rad", "yaw rad",
                                                             "qw ", "qx ", "qy ", "qz ", "wx rad/s",
                                                             "wy rad/s", "wz rad/s", "ax m/s²",
                                                             "ay m/s²", "az m/s²"});
    CHECK(names(SensorKind::contact) == std::vector<std::string>{"contact  bool", "force N"});
    CHECK(names(SensorKind::range) == std::vector<std::string>{"distance m", "hit  bool"});
    CHECK(names(SensorKind::position) ==
          std::vector<std::string>{"x m", "y m", "z m", "vx m/s", "vy m/s", "vz m/s"});
    CHECK(find_sensor_channel(SensorKind::imu, "pitch") == 1);
    CHECK(find_sensor_channel(SensorKind::imu, "angle") == -1);

    // users see degrees
    const SensorChannel& roll = sensor_channels(SensorKind::imu)[0];
    const SensorChannel& wx = sensor_channels(SensorKind::imu)[7];
    const SensorChannel& ax = sensor_channels(SensorKind::imu)[10];
    CHECK(user_unit(roll) == "deg");
    CHECK(user_unit(wx) == "deg/s");
    CHECK(user_unit(ax) == "m/s²");
    CHECK(to_user_units(roll, kPi / 2) == 90);
    CHECK(to_user_units(wx, kPi) == 180);
    CHECK(to_user_units(ax, 9.81) == 9.81);
}

TEST_CASE("a sensor must name a module or joint the robot has") {
    const RobotSpec r = snake(4);
    REQUIRE_NOTHROW(validate_sensor(r, of_kind(SensorKind::imu, 3)));
    REQUIRE_THROWS_AS(validate_sensor(r, of_kind(SensorKind::imu, 4)), SpecError);
    REQUIRE_THROWS_WITH(validate_sensor(r, of_kind(SensorKind::imu, 4)),
                        Equals("robot 'snake' has no module 5 (it has modules 1 to 4)"));
    REQUIRE_THROWS_WITH(validate_sensor(r, of_kind(SensorKind::contact, -1)),
                        Equals("robot 'snake' has no module 0 (it has modules 1 to 4)"));
    REQUIRE_THROWS_WITH(validate_sensor(r, of_kind(SensorKind::range, 9)),
                        Equals("robot 'snake' has no module 10 (it has modules 1 to 4)"));
    REQUIRE_THROWS_WITH(validate_sensor(r, of_kind(SensorKind::joint, 4)),
                        Equals("robot 'snake' has no joint 5 (it has joints 1 to 4)"));
    // a position sensor is the robot's, whatever its module field says
    REQUIRE_NOTHROW(validate_sensor(r, of_kind(SensorKind::position, 99)));

    RobotSpec lone;
    lone.name = "brick";
    lone.bodies.push_back(
        {"box", Shape::box, {0.1, 0.1, 0.1}, 1.0, {}, 1.0, std::nullopt, std::nullopt});
    REQUIRE_THROWS_WITH(validate_sensor(lone, of_kind(SensorKind::imu, 0)),
                        Equals("robot 'brick' has no modules"));
    REQUIRE_THROWS_WITH(validate_sensor(lone, of_kind(SensorKind::joint, 0)),
                        Equals("robot 'brick' has no joints"));
}

TEST_CASE("range sensors need a direction and a maximum range within limits") {
    const RobotSpec r = snake(2);
    SensorSpec s = of_kind(SensorKind::range, 1);
    s.max_range = 0;
    REQUIRE_THROWS_WITH(validate_sensor(r, s),
                        Equals("sensor 'range2' max_range must be in [0.01, 100] m (got 0)"));
    s.max_range = 150;
    REQUIRE_THROWS_WITH(validate_sensor(r, s),
                        Equals("sensor 'range2' max_range must be in [0.01, 100] m (got 150)"));
    s.max_range = std::numeric_limits<double>::quiet_NaN();
    REQUIRE_THROWS_WITH(validate_sensor(r, s),
                        Equals("sensor 'range2' max_range must be in [0.01, 100] m (got nan)"));
    s.max_range = 100;
    REQUIRE_NOTHROW(validate_sensor(r, s));
    s.max_range = 0.01;
    REQUIRE_NOTHROW(validate_sensor(r, s));
    s.direction = {0, 0, 0};
    REQUIRE_THROWS_WITH(validate_sensor(r, s),
                        Equals("sensor 'range2' direction must be a non-zero vector"));
    s.direction = {std::numeric_limits<double>::infinity(), 0, 0};
    REQUIRE_THROWS_WITH(validate_sensor(r, s),
                        Equals("sensor 'range2' direction must be a non-zero vector"));
    // any length but zero, also one whose norm underflows or overflows
    s.direction = {1e-300, 0, -1e-300};
    REQUIRE_NOTHROW(validate_sensor(r, s));
    s.direction = {1e300, 0, -1e300};
    REQUIRE_NOTHROW(validate_sensor(r, s));
    // only range sensors have a range: an IMU ignores the field
    SensorSpec i = of_kind(SensorKind::imu, 0);
    i.max_range = -1;
    REQUIRE_NOTHROW(validate_sensor(r, i));
}

TEST_CASE("an unnamed sensor on a module or joint out of range names the robot's range") {
    const RobotSpec r = snake(3);
    // not its default name 'imu-1', which is made of the number
    REQUIRE_THROWS_WITH(validate_sensor(r, of_kind(SensorKind::imu, -2)),
                        Equals("robot 'snake' has no module -1 (it has modules 1 to 3)"));
    REQUIRE_THROWS_WITH(validate_sensor(r, of_kind(SensorKind::joint, -5)),
                        Equals("robot 'snake' has no joint -4 (it has joints 1 to 3)"));
}

TEST_CASE("sensor names are unique within a robot and made of letters, digits and '_'") {
    RobotSpec r = snake(3);
    r.sensors.push_back(of_kind(SensorKind::imu, 2));
    REQUIRE_THROWS_WITH(validate_sensor(r, of_kind(SensorKind::imu, 2)),
                        Equals("robot 'snake' already has a sensor named 'imu3' (give this one "
                               "another name)"));
    SensorSpec named = of_kind(SensorKind::contact, 0);
    named.name = "imu3";
    REQUIRE_THROWS_WITH(validate_sensor(r, named),
                        Equals("robot 'snake' already has a sensor named 'imu3' (give this one "
                               "another name)"));
    named.name = "front imu";
    REQUIRE_THROWS_WITH(validate_sensor(r, named),
                        Equals("sensor name 'front imu' may contain only letters, digits and '_'"));
    named.name = "imu3.x";
    REQUIRE_THROWS_WITH(validate_sensor(r, named),
                        Equals("sensor name 'imu3.x' may contain only letters, digits and '_'"));
    named.name = "front_imu_2";
    REQUIRE_NOTHROW(validate_sensor(r, named));

    // the robot check sees every sensor
    r.sensors.push_back(of_kind(SensorKind::imu, 2));
    REQUIRE_THROWS_WITH(validate(r), Equals("robot 'snake' has two sensors named 'imu3'"));
    r.sensors.back() = of_kind(SensorKind::joint, 5);
    REQUIRE_THROWS_WITH(validate(r), Equals("robot 'snake' has no joint 6 (it has joints 1 to 3)"));
    WorldSpec w;
    w.robots.push_back({r, {}, {}});
    REQUIRE_THROWS_WITH(validate(w), Equals("robot 'snake' has no joint 6 (it has joints 1 to 3)"));
    // a simulation checks them before anything runs
    REQUIRE_THROWS_WITH(Simulation(w),
                        Equals("robot 'snake' has no joint 6 (it has joints 1 to 3)"));
}
