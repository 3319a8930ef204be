// Tests for engine/src/spec/module.cpp: the module library and module validation.
#include "gaitlab/module.h"

#include <catch2/catch.hpp>

#include <limits>

#include "gaitlab/error.h"
#include "gaitlab/robot.h"

using namespace gaitlab;
using Catch::Matchers::Equals;

TEST_CASE("the module library holds y1 first, then cube") {
    const std::vector<ModuleDef>& lib = builtin_modules();
    REQUIRE(lib.size() == 2);
    CHECK(lib[0].name == "y1");
    CHECK(lib[1].name == "cube");
    for (const ModuleDef& m : lib)
        CHECK_NOTHROW(validate(m));
}

TEST_CASE("y1 keeps its documented numbers") {
    const ModuleDef y1 = builtin_module("y1");
    CHECK(y1.shape == Shape::box);
    CHECK(y1.axis == JointAxis::bend);
    CHECK(y1.length == 0.072);
    CHECK(y1.width == 0.052);
    CHECK(y1.height == 0.052);
    CHECK(y1.mass == 0.05);
    CHECK(y1.min_angle == Approx(-kPi / 2));
    CHECK(y1.max_angle == Approx(kPi / 2));
    CHECK(y1.servo.kp == 8.3);
    CHECK(y1.servo.max_speed == 4.5);
    CHECK(y1.servo.max_torque == 0.4);
    CHECK(y1.friction == 1.0);
}

TEST_CASE("cube is a 60 mm cube module with a stronger servo") {
    const ModuleDef cube = builtin_module("cube");
    CHECK(cube.shape == Shape::box);
    CHECK(cube.length == 0.06);
    CHECK(cube.width == 0.06);
    CHECK(cube.height == 0.06);
    CHECK(cube.mass == 0.1);
    CHECK(cube.servo.max_torque == 1.0);
    CHECK(cube.servo.max_speed == 5.2);
    CHECK(cube.servo.kp == 8.3);
    CHECK(cube.max_angle == Approx(kPi / 2));
}

TEST_CASE("an unknown module type names the built-in ones") {
    REQUIRE_THROWS_AS(builtin_module("cub"), SpecError);
    REQUIRE_THROWS_WITH(builtin_module("cub"),
                        Equals("unknown module type 'cub' (built in: 'y1', 'cube')"));
}

TEST_CASE("module validation checks the fields of its shape") {
    ModuleDef m;
    m.name = "big";
    SECTION("a box needs a width") {
        m.width = -0.01;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'big' width must be positive (got -0.01 m)"));
    }
    SECTION("a cylinder needs a radius and ignores width and height") {
        m.shape = Shape::cylinder;
        m.width = -1;
        m.radius = 0.03;
        CHECK_NOTHROW(validate(m));
        m.radius = 0;
        REQUIRE_THROWS_WITH(validate(m), Equals("module 'big' radius must be positive (got 0 m)"));
    }
    SECTION("mass, friction, servo and range") {
        m.mass = std::numeric_limits<double>::quiet_NaN();
        REQUIRE_THROWS_WITH(validate(m), Equals("module 'big' mass must be positive (got nan kg)"));
        m.mass = 0.1;
        m.friction = 1.2;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'big' friction must be in [0, 1] (got 1.2)"));
        m.friction = 1;
        m.servo.max_speed = 0;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'big' servo max_speed must be positive (got 0 rad/s)"));
        m.servo.max_speed = 1;
        m.min_angle = 0.5;
        m.max_angle = 0.5;
        REQUIRE_THROWS_WITH(validate(m), Equals("module 'big' joint range must satisfy -180 <= "
                                                "min < max <= 180 deg"));
    }
    SECTION("servo values have upper bounds") {
        // kp = 1e308 or max_speed = 1e308 once passed and made the first step NaN
        m.servo.kp = 1e308;
        REQUIRE_THROWS_WITH(
            validate(m),
            Equals("module 'big' servo kp must be at most 1000000 1/s (got 1e+308 1/s)"));
        m.servo.kp = kMaxServoKp;
        m.servo.max_speed = 1e308;
        REQUIRE_THROWS_WITH(validate(m), Equals("module 'big' servo max_speed must be at most 1000 "
                                                "rad/s (got 1e+308 rad/s)"));
        m.servo.max_speed = kMaxServoSpeed;
        m.servo.max_torque = 2e9;
        REQUIRE_THROWS_WITH(validate(m), Equals("module 'big' servo max_torque must be at most "
                                                "1000000000 N·m (got 2000000000 N·m)"));
        m.servo.max_torque = kMaxServoTorque;
        CHECK_NOTHROW(validate(m));
        m.servo.kp = std::numeric_limits<double>::infinity();
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'big' servo kp must be positive (got inf 1/s)"));
    }
    SECTION("a module type needs a name") {
        m.name = "";
        REQUIRE_THROWS_WITH(validate(m), Equals("a module type needs a name"));
    }
}

TEST_CASE("module sizes and mass have lower bounds, twice a body's where a chain halves them") {
    // a mass of 1e-40 kg once made the first step NaN ("simulation diverged ... try a smaller
    // dt"), 1e-300 kg became 0 in single precision (a static body), a 1e-300 m module passed
    ModuleDef m;
    m.name = "m";
    SECTION("mass") {
        m.mass = 1e-40;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'm' mass must be at least 2e-09 kg (got 1e-40 kg)"));
        m.mass = 1e-300;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'm' mass must be at least 2e-09 kg (got 1e-300 kg)"));
        m.mass = 0;
        REQUIRE_THROWS_WITH(validate(m), Equals("module 'm' mass must be positive (got 0 kg)"));
        m.mass = 2 * kMinBodyMass;
        CHECK_NOTHROW(validate(m));
    }
    SECTION("a box's length, width and height") {
        m.length = 1e-300;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'm' length must be at least 0.0002 m (got 1e-300 m)"));
        m.length = 2 * kMinBodyExtent;
        m.width = 5e-5;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'm' width must be at least 0.0001 m (got 5e-05 m)"));
        m.width = kMinBodyExtent;
        m.height = 1e-6;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'm' height must be at least 0.0001 m (got 1e-06 m)"));
        m.height = kMinBodyExtent;
        CHECK_NOTHROW(validate(m));
    }
    SECTION("a cylinder's radius: no thinner than Bullet's collision margin") {
        m.shape = Shape::cylinder;
        m.radius = 5e-4;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'm' radius must be at least 0.001 m (got 0.0005 m)"));
        m.radius = kMinCylinderRadius;
        CHECK_NOTHROW(validate(m));
    }
    SECTION("a chain of modules at every lower bound is a valid robot") {
        for (Shape shape : {Shape::box, Shape::cylinder}) {
            m.shape = shape;
            m.length = 2 * kMinBodyExtent;
            m.width = m.height = kMinBodyExtent;
            m.radius = kMinCylinderRadius;
            m.mass = 2 * kMinBodyMass;
            ChainSpec chain;
            chain.module = m;
            chain.modules = 3;
            const RobotSpec robot = make_chain(chain);
            CHECK_NOTHROW(validate(robot));
            CHECK(robot.bodies.front().mass == kMinBodyMass);
            CHECK(robot.bodies.front().size.x == kMinBodyExtent);
        }
    }
}

TEST_CASE("a module's bodies are at most 300 times as long as their second longest side") {
    ModuleDef m = default_module_def();
    m.name = "m";
    SECTION("a box module: its segments a module long") {
        m.length = 1;
        m.width = m.height = 0.003;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'm' bodies' longest side must be at most 300 times "
                                   "its second longest (got 1 x 0.003 x 0.003 m: 333.333 times)"));
        m.width = m.height = 1.0 / kMaxBodySlenderness;
        CHECK_NOTHROW(validate(m));
    }
    SECTION("a box module: its end bodies half a module long") {
        m.length = 0.0004;
        m.width = 0.1;
        m.height = 0.0003;
        REQUIRE_THROWS_WITH(validate(m),
                            Equals("module 'm' bodies' longest side must be at most 300 times "
                                   "its second longest (got 0.0002 x 0.1 x 0.0003 m: 333.333 "
                                   "times; its end bodies are half a module)"));
        m.length = 0.001;
        CHECK_NOTHROW(validate(m));
    }
    SECTION("a cylinder module: its length over its diameter") {
        m.shape = Shape::cylinder;
        m.length = 1;
        m.radius = 0.001;
        REQUIRE_THROWS_WITH(validate(m), Equals("module 'm' length must be at most 300 times its "
                                                "diameter (got 1 m and 0.002 m: 500 times)"));
        m.length = 0.6;
        CHECK_NOTHROW(validate(m));
    }
}

TEST_CASE("joint axis names") {
    CHECK(std::string(to_string(JointAxis::bend)) == "bend");
    CHECK(std::string(to_string(JointAxis::twist)) == "twist");
    CHECK(std::string(to_string(Shape::cylinder)) == "cylinder");
}
