// Tests for engine/src/spec/robot.cpp: the chain builder, joint selection and robot validation.
#include "gaitlab/robot.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "gaitlab/error.h"

using namespace gaitlab;
using Catch::Matchers::Equals;
using Catch::Matchers::StartsWith;

namespace {

RobotSpec chain(int modules, Connection c, const char* name = "snake") {
    ChainSpec spec;
    spec.name = name;
    spec.modules = modules;
    spec.connection = c;
    return make_chain(spec);
}

ChainSpec chain_spec_with(const ModuleDef& module) {
    ChainSpec spec;
    spec.modules = 3;
    spec.module = module;
    return spec;
}

}  // namespace

TEST_CASE("make_chain builds N joints and N + 1 bodies laid along +x on the floor") {
    const int n = GENERATE(1, 2, 8);
    const Connection c =
        GENERATE(Connection::pitch_pitch, Connection::pitch_yaw, Connection::yaw_yaw);
    CAPTURE(n, to_string(c));
    const RobotSpec r = chain(n, c);

    REQUIRE(r.name == "snake");
    REQUIRE(r.bodies.size() == static_cast<size_t>(n + 1));
    REQUIRE(r.joints.size() == static_cast<size_t>(n));
    CHECK_FALSE(r.self_collision);

    // masses: 25 g tail half, N - 1 segments of 50 g, 25 g head half
    CHECK(r.bodies.front().name == "tail");
    CHECK(r.bodies.back().name == "head");
    CHECK(r.bodies.front().mass == Approx(0.025));
    CHECK(r.bodies.back().mass == Approx(0.025));
    for (int k = 1; k < n; ++k) {
        CHECK(r.bodies[k].name == "segment" + std::to_string(k));
        CHECK(r.bodies[k].mass == Approx(0.05));
    }
    CHECK(total_mass(r) == Approx(0.05 * n));

    // the bodies tile [0, 0.072 N] along x without gaps, 52 x 52 mm, bottom on the floor
    double x = 0;
    for (const BodySpec& b : r.bodies) {
        CAPTURE(b.name);
        CHECK(b.pose.position.x - b.size.x / 2 == Approx(x).margin(1e-12));
        x = b.pose.position.x + b.size.x / 2;
        CHECK(b.pose.position.y == 0);
        CHECK(b.pose.position.z == Approx(0.026));
        CHECK(b.pose.position.z - b.size.z / 2 == Approx(0).margin(1e-12));
        CHECK(b.size.y == Approx(0.052));
        CHECK(b.size.z == Approx(0.052));
        CHECK(b.pose.orientation == Quat{});
        CHECK(b.friction == 1.0);
    }
    CHECK(x == Approx(0.072 * n));

    // each joint sits at its module's mid-plane, between the two bodies it joins
    for (int j = 0; j < n; ++j) {
        const JointSpec& js = r.joints[j];
        CAPTURE(j);
        CHECK(js.name == "joint" + std::to_string(j + 1));
        CHECK(js.parent == j);
        CHECK(js.child == j + 1);
        CHECK(js.pivot.x == Approx(0.072 * (j + 0.5)));
        CHECK(js.pivot.y == 0);
        CHECK(js.pivot.z == Approx(0.026));
        const BodySpec& parent = r.bodies[js.parent];
        const BodySpec& child = r.bodies[js.child];
        CHECK(parent.pose.position.x + parent.size.x / 2 == Approx(js.pivot.x));
        CHECK(child.pose.position.x - child.size.x / 2 == Approx(js.pivot.x));
        CHECK(js.min_angle == Approx(-kPi / 2));
        CHECK(js.max_angle == Approx(kPi / 2));
        CHECK(js.servo.kp == 8.3);
        CHECK(js.servo.max_speed == 4.5);
        CHECK(js.servo.max_torque == 0.4);
    }
}

TEST_CASE("make_chain gives joints their roles and axes by connection type") {
    const int n = 8;
    SECTION("pitch-pitch: every joint pitches about -y (a positive angle lifts the head side)") {
        const RobotSpec r = chain(n, Connection::pitch_pitch);
        for (const JointSpec& j : r.joints) {
            CHECK(j.role == JointRole::pitch);
            CHECK(j.axis == Vec3{0, -1, 0});
        }
    }
    SECTION("yaw-yaw: every joint yaws about +z (a positive angle is counter-clockwise)") {
        const RobotSpec r = chain(n, Connection::yaw_yaw);
        for (const JointSpec& j : r.joints) {
            CHECK(j.role == JointRole::yaw);
            CHECK(j.axis == Vec3{0, 0, 1});
        }
    }
    SECTION("pitch-yaw: pitch first at the tail, then alternating") {
        const RobotSpec r = chain(n, Connection::pitch_yaw);
        for (int j = 0; j < n; ++j) {
            CAPTURE(j);
            const bool pitch = j % 2 == 0;
            CHECK(r.joints[j].role == (pitch ? JointRole::pitch : JointRole::yaw));
            CHECK(r.joints[j].axis == (pitch ? Vec3{0, -1, 0} : Vec3{0, 0, 1}));
        }
    }
    SECTION("a positive rotation about the pitch axis turns +x upward, about the yaw axis to +y") {
        const Quat pitch = Quat::from_axis_angle({0, -1, 0}, 0.3);
        const Quat yaw = Quat::from_axis_angle({0, 0, 1}, 0.3);
        CHECK(pitch.rotate({1, 0, 0}).z == Approx(std::sin(0.3)));
        CHECK(yaw.rotate({1, 0, 0}).y == Approx(std::sin(0.3)));
    }
}

TEST_CASE("connection and role names round-trip") {
    for (Connection c : {Connection::pitch_pitch, Connection::pitch_yaw, Connection::yaw_yaw}) {
        CHECK(parse_connection(to_string(c)) == c);
    }
    CHECK(std::string(to_string(Connection::pitch_yaw)) == "pitch-yaw");
    CHECK(std::string(to_string(JointRole::pitch)) == "pitch");
    CHECK(std::string(to_string(JointRole::yaw)) == "yaw");
    REQUIRE_THROWS_AS(parse_connection("pitch-roll"), SpecError);
    REQUIRE_THROWS_WITH(parse_connection("pitch-roll"),
                        Equals("unknown connection type 'pitch-roll' (expected 'pitch-pitch', "
                               "'pitch-yaw' or 'yaw-yaw')"));
    REQUIRE_THROWS_WITH(parse_connection(""),
                        Equals("unknown connection type '' (expected 'pitch-pitch', "
                               "'pitch-yaw' or 'yaw-yaw')"));
}

TEST_CASE("select_joints picks joints by role, from the tail") {
    SECTION("pitch-yaw") {
        const RobotSpec r = chain(8, Connection::pitch_yaw, "x");
        CHECK(select_joints(r, "pitch") == std::vector<int>{0, 2, 4, 6});
        CHECK(select_joints(r, "yaw") == std::vector<int>{1, 3, 5, 7});
        CHECK(select_joints(r, "all") == std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7});
    }
    SECTION("pitch-yaw with an odd number of modules ends with a pitch joint") {
        const RobotSpec r = chain(3, Connection::pitch_yaw, "x");
        CHECK(select_joints(r, "pitch") == std::vector<int>{0, 2});
        CHECK(select_joints(r, "yaw") == std::vector<int>{1});
    }
    SECTION("pitch-pitch has no yaw joints") {
        const RobotSpec r = chain(4, Connection::pitch_pitch, "x");
        CHECK(select_joints(r, "pitch") == std::vector<int>{0, 1, 2, 3});
        CHECK(select_joints(r, "all") == std::vector<int>{0, 1, 2, 3});
        REQUIRE_THROWS_AS(select_joints(r, "yaw"), SpecError);
        REQUIRE_THROWS_WITH(select_joints(r, "yaw"), Equals("robot 'x' has no yaw joints"));
    }
    SECTION("yaw-yaw has no pitch joints") {
        const RobotSpec r = chain(1, Connection::yaw_yaw, "worm");
        CHECK(select_joints(r, "yaw") == std::vector<int>{0});
        REQUIRE_THROWS_WITH(select_joints(r, "pitch"), Equals("robot 'worm' has no pitch joints"));
    }
    SECTION("unknown roles are errors") {
        const RobotSpec r = chain(2, Connection::pitch_yaw, "x");
        REQUIRE_THROWS_WITH(select_joints(r, "twist"),
                            Equals("unknown joint role 'twist' (expected 'pitch', 'yaw', 'roll' "
                                   "or 'all')"));
        REQUIRE_THROWS_WITH(select_joints(r, "Pitch"),
                            Equals("unknown joint role 'Pitch' (expected 'pitch', 'yaw', 'roll' "
                                   "or 'all')"));
        REQUIRE_THROWS_WITH(select_joints(r, "roll"), Equals("robot 'x' has no roll joints"));
    }
}

TEST_CASE("make_chain rejects a bad number of modules") {
    ChainSpec spec;
    spec.modules = 0;
    REQUIRE_THROWS_AS(make_chain(spec), SpecError);
    REQUIRE_THROWS_WITH(make_chain(spec), Equals("modules must be at least 1 (got 0)"));
    spec.modules = -3;
    REQUIRE_THROWS_WITH(make_chain(spec), Equals("modules must be at least 1 (got -3)"));
    spec.modules = 1001;
    REQUIRE_THROWS_WITH(make_chain(spec), Equals("modules must be at most 1000 (got 1001)"));
    spec.modules = 1000;
    CHECK(make_chain(spec).joints.size() == 1000);
}

TEST_CASE("make_chain rejects a bad module") {
    ModuleDef m = default_module_def();
    SECTION("negative mass") {
        m.mass = -0.05;
        REQUIRE_THROWS_AS(make_chain(chain_spec_with(m)), SpecError);
        REQUIRE_THROWS_WITH(make_chain(chain_spec_with(m)),
                            Equals("module 'y1' mass must be positive (got -0.05 kg)"));
    }
    SECTION("zero mass") {
        m.mass = 0;
        REQUIRE_THROWS_WITH(make_chain(chain_spec_with(m)),
                            Equals("module 'y1' mass must be positive (got 0 kg)"));
    }
    SECTION("not-a-number mass") {
        m.mass = std::numeric_limits<double>::quiet_NaN();
        REQUIRE_THROWS_WITH(make_chain(chain_spec_with(m)),
                            Equals("module 'y1' mass must be positive (got nan kg)"));
    }
    SECTION("friction above 1") {
        m.friction = 1.5;
        REQUIRE_THROWS_WITH(make_chain(chain_spec_with(m)),
                            Equals("module 'y1' friction must be in [0, 1] (got 1.5)"));
    }
    SECTION("negative friction") {
        m.friction = -0.1;
        REQUIRE_THROWS_WITH(make_chain(chain_spec_with(m)),
                            Equals("module 'y1' friction must be in [0, 1] (got -0.1)"));
    }
    SECTION("friction 0 and 1 are allowed") {
        m.friction = 0;
        CHECK(make_chain(chain_spec_with(m)).bodies[0].friction == 0);
        m.friction = 1;
        CHECK(make_chain(chain_spec_with(m)).bodies[0].friction == 1);
    }
    SECTION("zero length") {
        m.name = "cube";
        m.length = 0;
        REQUIRE_THROWS_WITH(make_chain(chain_spec_with(m)),
                            Equals("module 'cube' length must be positive (got 0 m)"));
    }
    SECTION("non-positive servo torque") {
        m.servo.max_torque = 0;
        REQUIRE_THROWS_WITH(make_chain(chain_spec_with(m)),
                            Equals("module 'y1' servo max_torque must be positive (got 0 N·m)"));
    }
    SECTION("empty or reversed joint range") {
        m.min_angle = 0.5;
        m.max_angle = 0.5;
        REQUIRE_THROWS_WITH(make_chain(chain_spec_with(m)),
                            Equals("module 'y1' joint range must satisfy -180 <= min < max <= "
                                   "180 deg"));
        m.min_angle = -4;
        m.max_angle = 1;
        REQUIRE_THROWS_AS(make_chain(chain_spec_with(m)), SpecError);
    }
}

TEST_CASE("a custom module scales the chain") {
    ModuleDef m = default_module_def();
    m.length = 0.1;
    m.height = 0.04;
    m.mass = 0.2;
    ChainSpec spec;
    spec.modules = 3;
    spec.module = m;
    const RobotSpec r = make_chain(spec);
    CHECK(total_mass(r) == Approx(0.6));
    CHECK(r.bodies.back().pose.position.x + r.bodies.back().size.x / 2 == Approx(0.3));
    CHECK(r.bodies[1].pose.position.z == Approx(0.02));
    CHECK(r.joints[2].pivot.x == Approx(0.25));
}

TEST_CASE("make_chain builds chains of any module of the library") {
    ChainSpec spec;
    spec.modules = 4;
    spec.module = builtin_module("cube");
    const RobotSpec r = make_chain(spec);
    REQUIRE(r.bodies.size() == 5);
    CHECK(r.bodies[0].size == Vec3{0.03, 0.06, 0.06});
    CHECK(r.bodies[1].size.x == Approx(0.06));
    CHECK(r.bodies[4].pose.position.x + r.bodies[4].size.x / 2 == Approx(0.24));
    CHECK(r.bodies[2].pose.position.z == Approx(0.03));  // resting on the floor
    CHECK(total_mass(r) == Approx(0.4));
    CHECK(r.joints[0].servo.max_torque == 1.0);
    CHECK(r.joints[0].pivot == Vec3{0.03, 0, 0.03});
}

TEST_CASE("cylinder modules make cylinder bodies along the chain") {
    ModuleDef m;
    m.name = "tube";
    m.shape = Shape::cylinder;
    m.radius = 0.02;
    m.length = 0.1;
    m.width = 0.5;  // ignored by a cylinder
    ChainSpec spec = chain_spec_with(m);
    spec.connection = Connection::pitch_yaw;
    const RobotSpec r = make_chain(spec);
    for (const BodySpec& b : r.bodies) {
        CHECK(b.shape == Shape::cylinder);
        CHECK(b.size.y == Approx(0.04));
        CHECK(b.size.z == Approx(0.04));
        CHECK(b.pose.position.z == Approx(0.02));
    }
    CHECK(r.joints[1].role == JointRole::yaw);
    CHECK_NOTHROW(validate(r));
}

TEST_CASE("twist modules make roll joints about the chain's axis") {
    ModuleDef m;
    m.name = "roller";
    m.axis = JointAxis::twist;
    const Connection c =
        GENERATE(Connection::pitch_pitch, Connection::pitch_yaw, Connection::yaw_yaw);
    ChainSpec spec = chain_spec_with(m);
    spec.connection = c;
    const RobotSpec r = make_chain(spec);
    for (const JointSpec& j : r.joints) {
        CHECK(j.role == JointRole::roll);
        CHECK(j.axis == Vec3{1, 0, 0});
    }
    CHECK(select_joints(r, "roll") == std::vector<int>{0, 1, 2});
    CHECK(std::string(to_string(JointRole::roll)) == "roll");
}

TEST_CASE("a pitch-yaw chain of box modules needs a square cross-section") {
    ModuleDef m;
    m.name = "flat";
    m.height = 0.03;
    ChainSpec spec = chain_spec_with(m);
    CHECK_NOTHROW(make_chain(spec));  // pitch-pitch: fine
    spec.connection = Connection::pitch_yaw;
    REQUIRE_THROWS_WITH(make_chain(spec),
                        Equals("a pitch-yaw chain needs modules with a square cross-section "
                               "(module 'flat' is 0.052 x 0.03 m; make width = height or use a "
                               "cylinder)"));
}

TEST_CASE("validate(RobotSpec) rejects broken robots") {
    RobotSpec r = chain(2, Connection::pitch_pitch, "x");
    REQUIRE_NOTHROW(validate(r));
    SECTION("no bodies") {
        r.bodies.clear();
        r.joints.clear();
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' has no bodies"));
    }
    SECTION("a body with negative mass") {
        r.bodies[1].mass = -1;
        REQUIRE_THROWS_WITH(validate(r),
                            Equals("robot 'x' body 'segment1' mass must be positive (got -1 kg)"));
    }
    SECTION("a body with friction outside [0, 1]") {
        r.bodies[0].friction = 2;
        REQUIRE_THROWS_WITH(validate(r),
                            Equals("robot 'x' body 'tail' friction must be in [0, 1] (got 2)"));
    }
    SECTION("a joint joining a body to itself or to no body") {
        r.joints[0].child = 0;
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' joint 'joint1' must join two "
                                                "different bodies of the robot"));
        r.joints[0].child = 3;
        REQUIRE_THROWS_AS(validate(r), SpecError);
    }
    SECTION("a joint axis that is not a unit vector") {
        r.joints[1].axis = {0, 0, 2};
        REQUIRE_THROWS_WITH(validate(r),
                            Equals("robot 'x' joint 'joint2' axis must be a unit vector"));
    }
    SECTION("a cylinder body with two diameters") {
        r.bodies[1].shape = Shape::cylinder;
        REQUIRE_NOTHROW(validate(r));
        r.bodies[1].size.z = 0.06;
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' body 'segment1' is a cylinder: size y "
                                                "and z (its diameter) must be equal"));
    }
    SECTION("a joint with an empty range") {
        r.joints[1].min_angle = 1;
        r.joints[1].max_angle = -1;
        REQUIRE_THROWS_WITH(validate(r),
                            Equals("robot 'x' joint 'joint2' range must have min < max"));
    }
    SECTION("a joint range beyond half a turn either way") {
        // as a module's range: a URDF <limit lower="-100" upper="100"> once passed as +-5730 deg
        r.joints[1].min_angle = -100;
        r.joints[1].max_angle = 100;
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' joint 'joint2' range must satisfy -180 "
                                                "<= min < max <= 180 deg (got -5729.5779513082325 "
                                                "to 5729.5779513082325 deg)"));
        r.joints[1].min_angle = -kPi;
        r.joints[1].max_angle = 3.2;
        REQUIRE_THROWS_WITH(validate(r), StartsWith("robot 'x' joint 'joint2' range must satisfy "
                                                    "-180 <= min < max <= 180 deg (got -180 to "
                                                    "183.3"));
        r.joints[1].max_angle = kPi;
        CHECK_NOTHROW(validate(r));
    }
    SECTION("a joint's servo beyond its bounds") {
        r.joints[1].servo.max_speed = 1e308;
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' joint 'joint2' servo max_speed must be "
                                                "at most 1000 rad/s (got 1e+308 rad/s)"));
        r.joints[1].servo.max_speed = 1;
        r.joints[1].servo.max_torque = 1e308;
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' joint 'joint2' servo max_torque must be "
                                                "at most 1000000000 N·m (got 1e+308 N·m)"));
        r.joints[1].servo.max_torque = 1;
        r.joints[1].servo.kp = 2e6;
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' joint 'joint2' servo kp must be at most "
                                                "1000000 1/s (got 2000000 1/s)"));
    }
}

TEST_CASE("a body's mass and sizes have lower bounds, a cylinder's diameter Bullet's margin's") {
    RobotSpec r = chain(2, Connection::pitch_pitch, "x");
    BodySpec& b = r.bodies[1];
    SECTION("mass") {
        b.mass = 1e-300;
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' body 'segment1' mass must be at least "
                                                "1e-09 kg (got 1e-300 kg)"));
        b.mass = kMinBodyMass;
        CHECK_NOTHROW(validate(r));
    }
    SECTION("sizes of a box") {
        b.size.x = 1e-300;
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' body 'segment1' size x must be at least "
                                                "0.0001 m (got 1e-300 m)"));
        b.size = {kMinBodyExtent, 1e-5, kMinBodyExtent};
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' body 'segment1' size y must be at least "
                                                "0.0001 m (got 1e-05 m)"));
        b.size = {kMinBodyExtent, kMinBodyExtent, 9e-5};
        REQUIRE_THROWS_WITH(validate(r), Equals("robot 'x' body 'segment1' size z must be at least "
                                                "0.0001 m (got 9e-05 m)"));
        b.size.z = kMinBodyExtent;
        CHECK_NOTHROW(validate(r));
    }
    SECTION("a cylinder's diameter") {
        b.shape = Shape::cylinder;
        b.size = {kMinBodyExtent, 1e-3, 1e-3};
        REQUIRE_THROWS_WITH(validate(r),
                            Equals("robot 'x' body 'segment1' size y (a cylinder's diameter) must "
                                   "be at least 0.002 m (got 0.001 m)"));
        b.size.y = b.size.z = 2 * kMinCylinderRadius;
        CHECK_NOTHROW(validate(r));
    }
}

TEST_CASE("a body's longest side is at most 300 times its second longest") {
    RobotSpec r = chain(2, Connection::pitch_pitch, "x");
    BodySpec& b = r.bodies[1];
    SECTION("a box, the second longest side setting the bound (the third may be thinner)") {
        b.size = {1, 0.003, 0.0003};
        REQUIRE_THROWS_WITH(validate(r),
                            Equals("robot 'x' body 'segment1' longest side must be at most 300 "
                                   "times its second longest (got 1 x 0.003 x 0.0003 m: 333.333 "
                                   "times)"));
        b.size = {0.0001, 0.0003, 0.1};
        REQUIRE_THROWS_WITH(validate(r),
                            Equals("robot 'x' body 'segment1' longest side must be at most 300 "
                                   "times its second longest (got 0.0001 x 0.0003 x 0.1 m: "
                                   "333.333 times)"));
        b.size = {1, 1.0 / kMaxBodySlenderness, 1e-4};
        CHECK_NOTHROW(validate(r));
        // a plate is not slender: two long sides
        b.size = {1, 1, 1e-4};
        CHECK_NOTHROW(validate(r));
    }
    SECTION("a cylinder, its length over its diameter") {
        b.shape = Shape::cylinder;
        b.size = {1, 0.002, 0.002};
        REQUIRE_THROWS_WITH(validate(r),
                            Equals("robot 'x' body 'segment1' length must be at most 300 times "
                                   "its diameter (got 1 m and 0.002 m: 500 times)"));
        b.size.x = 0.6;
        CHECK_NOTHROW(validate(r));
        // a disc is not slender
        b.size = {1e-4, 1, 1};
        CHECK_NOTHROW(validate(r));
    }
}

TEST_CASE("a body's given inertia is positive, fits its mass and size, and is a body's") {
    RobotSpec r = chain(2, Connection::pitch_pitch, "x");
    BodySpec& b = r.bodies[1];
    b.size = {0.1, 0.1, 0.1};
    b.mass = 1;
    const auto refused = [&](const Vec3& inertia) {
        b.inertia = inertia;
        try {
            validate(r);
        } catch (const SpecError& e) {
            return std::string(e.what());
        }
        FAIL("no error");
        return std::string();
    };
    CHECK_THAT(refused({-1e-3, 1e-3, 1e-3}),
               Equals("robot 'x' body 'segment1' inertia x must be positive (got -0.001 kg·m²)"));
    CHECK_THAT(refused({1e-3, std::nan(""), 1e-3}),
               Equals("robot 'x' body 'segment1' inertia y must be positive (got nan kg·m²)"));
    CHECK_THAT(refused({1e-3, 1e-3, std::numeric_limits<double>::infinity()}),
               Equals("robot 'x' body 'segment1' inertia z must be positive (got inf kg·m²)"));
    // from a hundredth of the uniform cube's (1/600 kg·m²) to all of the mass at its corners
    CHECK_THAT(refused({0.008, 0.008, 0.008}),
               Equals("robot 'x' body 'segment1' inertia x must be in [1.66667e-05, 0.0075] kg·m² "
                      "for its mass and size (got 0.008): from 0.01 of the uniform solid's to all "
                      "of its mass at half its diagonal"));
    CHECK_THAT(refused({1e-3, 1e-9, 1e-3}),
               StartsWith("robot 'x' body 'segment1' inertia y must be in [1.66667e-05, 0.0075]"));
    // the bounds themselves are inside, written as the message prints them or as the solid's
    // moment / 100 (one rounding step below 0.01 times it), for boxes and cylinders
    b.inertia = Vec3{1.66667e-05, 1.66667e-05, 1.66667e-05};
    CHECK_NOTHROW(validate(r));
    b.inertia = Vec3{0.0075, 0.00375, 0.00375};
    CHECK_NOTHROW(validate(r));
    for (const Shape shape : {Shape::box, Shape::cylinder}) {
        b.shape = shape;
        b.inertia.reset();
        const Vec3 solid = body_inertia(b);
        b.inertia = Vec3{solid.x / 100, solid.y / 100, solid.z / 100};
        CHECK_NOTHROW(validate(r));
    }
    b.shape = Shape::box;
    // no more uneven than a body 300 times as long as wide: a rod that slender, whose solid's
    // moment about its axis is 45 000 times smaller than about the others, may not have
    // 100 000 times
    b.size = {1, 1.0 / 300, 1.0 / 300};
    CHECK_THAT(refused({2e-8, 2e-3, 2e-3}),
               Equals("robot 'x' body 'segment1' inertia's largest moment must be at most 90000 "
                      "times its smallest, as a body's at most 300 times as long as wide (got "
                      "2e-08 0.002 0.002 kg·m²: 100000 times)"));
    b.size = {0.1, 0.1, 0.1};
    CHECK_THAT(refused({1e-3, 3e-3, 1e-3}),
               Equals("robot 'x' body 'segment1' inertia must have each moment at most the sum "
                      "of the other two, as every body's has (got 0.001 0.003 0.001 kg·m²: y is "
                      "0.003, the other two add up to 0.002)"));
    // a thin plate's: its z moment the sum of the other two
    b.inertia = Vec3{1e-3, 2e-3, 3e-3};
    CHECK_NOTHROW(validate(r));
    // every body's own solid's inertia, given, is accepted: the bounds are the solids'
    for (const auto& [shape, size] :
         {std::pair{Shape::box, Vec3{1, 1.0 / 300, 1e-4}}, std::pair{Shape::box, Vec3{1, 1, 1e-4}},
          std::pair{Shape::box, Vec3{1e-4, 1e-4, 1e-4}}, std::pair{Shape::box, Vec3{100, 100, 100}},
          std::pair{Shape::cylinder, Vec3{0.6, 0.002, 0.002}},
          std::pair{Shape::cylinder, Vec3{1e-4, 100, 100}}}) {
        for (double mass : {kMinBodyMass, 1.0, kMaxBodyMass}) {
            CAPTURE(size.x, size.y, size.z, mass);
            b.shape = shape;
            b.size = size;
            b.mass = mass;
            b.inertia.reset();
            b.inertia = body_inertia(b);
            CHECK_NOTHROW(validate(r));
        }
    }
}

TEST_CASE("a body's centre of mass is finite and inside its shape") {
    RobotSpec r = chain(2, Connection::pitch_pitch, "x");
    BodySpec& b = r.bodies[1];
    b.size = {0.2, 0.1, 0.1};
    const auto refused = [&](const Vec3& com) {
        b.center_of_mass = com;
        try {
            validate(r);
        } catch (const SpecError& e) {
            return std::string(e.what());
        }
        FAIL("no error");
        return std::string();
    };
    CHECK_THAT(refused({0.11, 0, 0}),
               Equals("robot 'x' body 'segment1' com must lie inside the box: each coordinate "
                      "within half its size, ±0.1 ±0.05 ±0.05 m (got 0.11 0 0 m)"));
    CHECK_THAT(refused({0, -0.06, 0}), StartsWith("robot 'x' body 'segment1' com must lie inside"));
    CHECK_THAT(refused({0, 0, std::nan("")}),
               Equals("robot 'x' body 'segment1' com must be a finite number"));
    CHECK_THAT(refused({std::numeric_limits<double>::infinity(), 0, 0}),
               Equals("robot 'x' body 'segment1' com must be a finite number"));
    // its boundary is inside: all the mass on a face, an edge, a corner
    for (const Vec3& c : {Vec3{0.1, 0, 0}, Vec3{-0.1, 0.05, 0}, Vec3{0.1, -0.05, 0.05}, Vec3{}}) {
        b.center_of_mass = c;
        CHECK_NOTHROW(validate(r));
    }
    // a cylinder's within its radius of its axis: the box's corner is not
    b.shape = Shape::cylinder;
    b.size = {0.2, 0.1, 0.1};
    b.center_of_mass = Vec3{0.1, 0.05, 0};
    CHECK_NOTHROW(validate(r));
    CHECK_THAT(refused({0, 0.04, 0.04}),
               Equals("robot 'x' body 'segment1' com must lie inside the cylinder: x within ±0.1 "
                      "m (half its length), y and z within 0.05 m of its axis (its radius) (got 0 "
                      "0.04 0.04 m)"));
    // equality sees it
    RobotSpec other = r;
    b.center_of_mass = Vec3{0.01, 0, 0};
    other.bodies[1].center_of_mass.reset();
    CHECK_FALSE(r == other);
    other.bodies[1].center_of_mass = Vec3{0.01, 0, 0};
    CHECK(r == other);
}

TEST_CASE("names are valid UTF-8 without control characters", "[names]") {
    RobotSpec r = chain(2, Connection::pitch_pitch);
    const auto rejected = [&](const std::string& message) {
        REQUIRE_THROWS_WITH(validate(r), Equals(message));
    };
    for (const char* ok : {"snake", "serpent à sonnettes", "蛇", "a/b c", "🐍"}) {
        r.name = ok;
        CHECK_NOTHROW(validate(r));
    }
    r.name = std::string("snake\n1");
    rejected("robot name must be valid UTF-8 without control characters (got \"snake\\x0a1\")");
    r.name = "snake\x7f";
    rejected("robot name must be valid UTF-8 without control characters (got \"snake\\x7f\")");
    r.name = "\xc2\x85";  // U+0085, a C1 control
    rejected("robot name must be valid UTF-8 without control characters (got \"\\xc2\\x85\")");
    r.name = "bad\xff";
    rejected("robot name must be valid UTF-8 without control characters (got \"bad\\xff\")");
    r.name = "\xc0\xaf";  // an overlong '/'
    rejected("robot name must be valid UTF-8 without control characters (got \"\\xc0\\xaf\")");
    r.name = "\xed\xa0\x80";  // a surrogate
    rejected("robot name must be valid UTF-8 without control characters (got \"\\xed\\xa0\\x80\")");
    r.name = "cut\xe8\x9b";  // a truncated sequence
    rejected("robot name must be valid UTF-8 without control characters (got \"cut\\xe8\\x9b\")");
    r.name = std::string("nul\0", 4);
    rejected("robot name must be valid UTF-8 without control characters (got \"nul\\x00\")");
    r.name = std::string(300, 'a');
    rejected("robot name must be at most 256 bytes long (got 300 bytes)");
    r.name = "";
    rejected("a robot needs a name");
    r.name = "snake";
    r.bodies[1].name = "seg\tment";
    rejected(
        "robot 'snake' body 'seg\tment' name must be valid UTF-8 without control characters "
        "(got \"seg\\x09ment\")");
    r.bodies[1].name = "segment1";
    r.joints[0].name = "j\x01";
    rejected(
        "robot 'snake' joint 'j\x01' name must be valid UTF-8 without control characters "
        "(got \"j\\x01\")");
    ChainSpec c;
    c.name = "a\x1b[31m";  // an escape sequence a terminal would act on
    REQUIRE_THROWS_WITH(make_chain(c), Equals("robot name must be valid UTF-8 without control "
                                              "characters (got \"a\\x1b[31m\")"));
}

TEST_CASE("robots are bounded in size and their checks stay fast", "[limits]") {
    RobotSpec r = chain(2, Connection::pitch_pitch);
    // many bodies: duplicate names are found without comparing every pair
    RobotSpec big;
    big.name = "big";
    for (int b = 0; b < kMaxRobotBodies; ++b) {
        BodySpec body = r.bodies[0];
        body.name = "b" + std::to_string(b);
        body.pose.position.x = b * 0.04;
        big.bodies.push_back(body);
    }
    CHECK_NOTHROW(validate(big));
    big.bodies.back().name = "b0";
    REQUIRE_THROWS_WITH(validate(big), Equals("robot 'big' has two bodies named 'b0'"));
    big.bodies.back().name = "last";
    big.bodies.push_back(big.bodies.back());
    REQUIRE_THROWS_WITH(
        validate(big), Equals("robot 'big' has 10001 bodies and 0 joints (at most 10000 of each)"));
    r.bodies[0].size.x = 1e6;
    REQUIRE_THROWS_WITH(validate(r),
                        Equals("robot 'snake' body 'tail' size x must be at most 100 m (got "
                               "1000000 m)"));
}
