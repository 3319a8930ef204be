// Tests for engine/src/spec/world.cpp: world spec validation (directly and through Simulation).
#include "gaitlab/world.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <memory>

#include "gaitlab/controller.h"
#include "gaitlab/error.h"
#include "gaitlab/simulation.h"

#include "engine/sim_support.h"

using namespace gaitlab;
using Catch::Matchers::Equals;
using Catch::Matchers::StartsWith;

namespace {

WorldSpec world_with_robot() {
    ChainSpec chain;
    chain.name = "snake";
    chain.modules = 2;
    WorldSpec w;
    PlacedRobot placed;
    placed.robot = make_chain(chain);
    w.robots.push_back(std::move(placed));
    return w;
}

// the world must be rejected with `message`, by validate() and by the Simulation that compiles it
void require_rejected(const WorldSpec& w, const std::string& message) {
    REQUIRE_THROWS_AS(validate(w), SpecError);
    REQUIRE_THROWS_WITH(validate(w), Equals(message));
    REQUIRE_THROWS_WITH(Simulation(w), Equals(message));
}

}  // namespace

TEST_CASE("a default world with a robot is valid") {
    const WorldSpec w = world_with_robot();
    REQUIRE_NOTHROW(validate(w));
    CHECK(w.gravity.z == -9.81);
    CHECK(w.floor.enabled);
    CHECK(w.floor.friction == 1.0);
}

TEST_CASE("floor friction must be in [0, 1]") {
    WorldSpec w = world_with_robot();
    w.floor.friction = 1.5;
    require_rejected(w, "floor friction must be in [0, 1] (got 1.5)");
    w.floor.friction = -0.2;
    require_rejected(w, "floor friction must be in [0, 1] (got -0.2)");
    w.floor.friction = std::numeric_limits<double>::quiet_NaN();
    require_rejected(w, "floor friction must be in [0, 1] (got nan)");
    w.floor.friction = 0;
    CHECK_NOTHROW(validate(w));
    w.floor.friction = 1;
    CHECK_NOTHROW(validate(w));
}

TEST_CASE("the floor's stiffness and damping are in range, and a rigid floor takes neither") {
    WorldSpec w = world_with_robot();
    // compliant by default, each value its default until given
    CHECK_FALSE(w.floor.rigid);
    CHECK_FALSE(w.floor.stiffness);
    CHECK_FALSE(w.floor.damping);
    w.floor.stiffness = 1e4;
    CHECK_NOTHROW(validate(w));
    w.floor.stiffness.reset();
    w.floor.damping = 20;
    CHECK_NOTHROW(validate(w));
    w.floor.rigid = true;
    require_rejected(w,
                     "a rigid floor takes no damping (a floor is rigid, or compliant with a "
                     "stiffness and a damping)");
    w.floor.stiffness = 1e4;
    require_rejected(w,
                     "a rigid floor takes no stiffness (a floor is rigid, or compliant with a "
                     "stiffness and a damping)");
    w.floor.stiffness.reset();
    w.floor.damping.reset();
    CHECK_NOTHROW(validate(w));
    w.floor.rigid = false;
    w.floor.stiffness = 1e4;
    w.floor.damping = 20;
    CHECK_NOTHROW(validate(w));
    w.floor.damping = 0;
    CHECK_NOTHROW(validate(w));
    w.floor.damping = -1;
    require_rejected(w, "floor damping must not be negative (got -1 N·s/m)");
    w.floor.damping = std::numeric_limits<double>::infinity();
    require_rejected(w, "floor damping must not be negative (got inf N·s/m)");
    w.floor.damping = 2e12;
    require_rejected(w,
                     "floor damping must be at most 1000000000000 N·s/m (got 2000000000000 "
                     "N·s/m)");
    w.floor.damping = 20;
    w.floor.stiffness = 0;
    require_rejected(w, "floor stiffness must be positive (got 0 N/m)");
    w.floor.stiffness = -5;
    require_rejected(w, "floor stiffness must be positive (got -5 N/m)");
    w.floor.stiffness = std::numeric_limits<double>::quiet_NaN();
    require_rejected(w, "floor stiffness must be positive (got nan N/m)");
    w.floor.stiffness = 1e13;
    require_rejected(w,
                     "floor stiffness must be at most 1000000000000 N/m (got 10000000000000 "
                     "N/m)");
    w.floor.stiffness = kMaxFloorStiffness;
    w.floor.damping = kMaxFloorDamping;
    CHECK_NOTHROW(validate(w));
}

TEST_CASE("boxes are checked and numbered from 1") {
    WorldSpec w = world_with_robot();
    w.boxes.resize(2);
    w.boxes[0].pose.position = {1, 0, 0.05};
    w.boxes[1].pose.position = {-1, 0, 0.05};
    REQUIRE_NOTHROW(validate(w));
    SECTION("negative mass") {
        w.boxes[1].mass = -1;
        require_rejected(w, "box 2 mass must not be negative (got -1 kg)");
    }
    SECTION("zero size") {
        w.boxes[0].size.y = 0;
        require_rejected(w, "box 1 size y must be positive (got 0 m)");
    }
    SECTION("friction above 1") {
        w.boxes[0].friction = 3;
        require_rejected(w, "box 1 friction must be in [0, 1] (got 3)");
    }
    SECTION("infinite position") {
        w.boxes[1].pose.position.z = std::numeric_limits<double>::infinity();
        require_rejected(w, "box 2 position z must be a finite number");
    }
    SECTION("an orientation that is not a rotation") {
        w.boxes[0].pose.orientation = Quat::from_axis_angle({0, 0, 1}, std::nan(""));
        require_rejected(w, "box 1 orientation must be a unit quaternion");
    }
}

TEST_CASE("gravity must be finite and within 1000 m/s² on each axis") {
    WorldSpec w = world_with_robot();
    w.gravity.x = std::numeric_limits<double>::quiet_NaN();
    require_rejected(w, "gravity x must be a finite number");
    w.gravity.x = 0;
    w.gravity.z = -1e30;
    require_rejected(w, "gravity z must be in [-1000, 1000] m/s² (got -1e+30)");
    w.gravity.z = 1000.5;
    require_rejected(w, "gravity z must be in [-1000, 1000] m/s² (got 1000.5)");
    w.gravity = {1000, -1000, -1000};
    CHECK_NOTHROW(validate(w));
}

TEST_CASE("positions, sizes and masses beyond what single-precision physics means are refused") {
    WorldSpec w = world_with_robot();
    SECTION("a box far away") {
        w.boxes.resize(1);
        w.boxes[0].pose.position.x = 1e30;
        require_rejected(w, "box 1 position x must be in [-10000, 10000] m (got 1e+30)");
    }
    SECTION("a box larger than the world") {
        w.boxes.resize(1);
        w.boxes[0].size.x = 1e30;
        require_rejected(w, "box 1 size x must be at most 10000 m (got 1e+30 m)");
    }
    SECTION("a box heavier than anything a robot meets") {
        w.boxes.resize(1);
        w.boxes[0].mass = 1e30;
        require_rejected(w, "box 1 mass must be at most 1000000 kg (got 1e+30 kg)");
    }
    SECTION("stairs whose steps add up beyond the limit") {
        w.stairs.resize(1);
        w.stairs[0].steps = 1000;
        w.stairs[0].step_height = 9000;
        require_rejected(w, "stairs 1 height must be at most 10000 m (got 9000000 m)");
    }
    SECTION("a robot far away") {
        w.robots[0].pose.position.y = -2e4;
        require_rejected(w, "robot 'snake' position y must be in [-10000, 10000] m (got -20000)");
    }
    SECTION("a robot body") {
        w.robots[0].robot.bodies[1].mass = 1e9;
        require_rejected(
            w, "robot 'snake' body 'segment1' mass must be at most 1000000 kg (got 1000000000 kg)");
    }
}

TEST_CASE("sizes and masses too small for single-precision physics are refused with their bound") {
    // each was accepted before, down to 1e-300, and became 0 or a denormal in Bullet's floats
    WorldSpec w = world_with_robot();
    SECTION("boxes") {
        w.boxes.resize(1);
        w.boxes[0].size.y = 1e-300;
        require_rejected(w, "box 1 size y must be at least 0.0001 m (got 1e-300 m)");
        w.boxes[0].size.y = kMinExtent;
        w.boxes[0].mass = 1e-300;
        require_rejected(w, "box 1 mass must be 0 (static) or at least 1e-09 kg (got 1e-300 kg)");
        w.boxes[0].mass = kMinObjectMass;
        CHECK_NOTHROW(validate(w));
        w.boxes[0].mass = 0;
        CHECK_NOTHROW(validate(w));
    }
    SECTION("cylinders: the radius no smaller than Bullet's collision margin") {
        w.cylinders.resize(1);
        w.cylinders[0].radius = 9e-4;
        require_rejected(w, "cylinder 1 radius must be at least 0.001 m (got 0.0009 m)");
        w.cylinders[0].radius = kMinCylinderRadius;
        w.cylinders[0].length = 1e-5;
        require_rejected(w, "cylinder 1 length must be at least 0.0001 m (got 1e-05 m)");
        w.cylinders[0].length = kMinExtent;
        w.cylinders[0].mass = 1e-40;
        require_rejected(w,
                         "cylinder 1 mass must be 0 (static) or at least 1e-09 kg (got 1e-40 kg)");
        w.cylinders[0].mass = kMinObjectMass;
        CHECK_NOTHROW(validate(w));
    }
    SECTION("walls, ramps, stairs, pipes") {
        w.walls.resize(1);
        w.walls[0].thickness = 1e-300;
        require_rejected(w, "wall 1 thickness must be at least 0.0001 m (got 1e-300 m)");
        w.walls[0].thickness = kMinExtent;
        w.ramps.resize(1);
        w.ramps[0].width = 1e-300;
        require_rejected(w, "ramp 1 width must be at least 0.0001 m (got 1e-300 m)");
        w.ramps[0].width = kMinExtent;
        // a slope so gentle that the wedge is thinner than the bound
        w.ramps[0].length = 1;
        w.ramps[0].slope = 1e-5;
        REQUIRE_THROWS_WITH(validate(w),
                            StartsWith("ramp 1 height must be at least 0.0001 m (got 1.0000000"));
        w.ramps[0].slope = 1e-4;
        w.stairs.resize(1);
        w.stairs[0].step_depth = 1e-300;
        require_rejected(w, "stairs 1 step_depth must be at least 0.0001 m (got 1e-300 m)");
        w.stairs[0].step_depth = kMinExtent;
        w.pipes.resize(1);
        w.pipes[0].thickness = 1e-300;
        require_rejected(w, "pipe 1 thickness must be at least 0.0001 m (got 1e-300 m)");
        w.pipes[0].thickness = kMinExtent;
        CHECK_NOTHROW(validate(w));
    }
    SECTION("rubble and heightfields") {
        w.rubble.resize(1);
        w.rubble[0].min_size = 1e-300;
        require_rejected(w, "rubble 1 min_size must be at least 0.0001 m (got 1e-300 m)");
        w.rubble[0].min_size = kMinExtent;
        w.rubble[0].min_height = 1e-300;
        require_rejected(w, "rubble 1 min_height must be at least 0.0001 m (got 1e-300 m)");
        w.rubble[0].min_height = kMinExtent;
        w.heightfields.resize(1);
        HeightfieldSpec& h = w.heightfields[0];
        h.image = "x.png";
        h.length = 1e-300;
        require_rejected(w, "heightfield 1 length must be at least 0.0001 m (got 1e-300 m)");
        h.length = kMinExtent;
        h.max_height = 1e-300;
        REQUIRE_THROWS_WITH(validate(w), Equals("heightfield 1 max_height must be at least 0.0001 "
                                                "m (got 1e-300 m)"));
        h.max_height = kMinExtent;
        CHECK_NOTHROW(validate(w));
    }
    SECTION("a robot body") {
        w.robots[0].robot.bodies[0].mass = 1e-40;
        require_rejected(w,
                         "robot 'snake' body 'tail' mass must be at least 1e-09 kg (got 1e-40 kg)");
    }
}

namespace {

// a travelling wave on every joint of its group: amplitude 40 deg, 1 Hz, 120 deg between joints
class Wave final : public Controller {
  public:
    Wave() : Controller(ControllerDef{"wave", {}, {}}) {}
    void step(ControlIO& io) override {
        for (int m = 0; m < io.joints(); ++m)
            io.set_target(m, deg_to_rad(40) * std::sin(2 * kPi * io.time() - m * deg_to_rad(120)));
    }
};

bool finite(const BodyState& b) {
    const Vec3& p = b.pose.position;
    const Vec3& v = b.linear_velocity;
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(v.x) &&
           std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

TEST_CASE("a world at the lower bounds simulates at the default dt and solver") {
    // a chain of the smallest, lightest modules under a wave gait, and the smallest, lightest
    // box and cylinders dropped onto the floor, 1 s at dt 1 ms
    for (Shape shape : {Shape::box, Shape::cylinder}) {
        CAPTURE(shape == Shape::box ? "box modules" : "cylinder modules");
        ChainSpec chain;
        chain.name = "snake";
        chain.modules = 8;
        chain.module.shape = shape;
        chain.module.length = 2 * kMinBodyExtent;
        chain.module.width = chain.module.height = kMinBodyExtent;
        chain.module.radius = kMinCylinderRadius;
        chain.module.mass = 2 * kMinBodyMass;
        WorldSpec w;
        w.floor.friction = 0.8;
        PlacedRobot placed;
        placed.robot = make_chain(chain);
        w.robots.push_back(std::move(placed));
        BoxSpec box;
        box.size = {kMinExtent, kMinExtent, kMinExtent};
        box.mass = kMinObjectMass;
        box.pose.position = {0, 0.01, 2 * kMinExtent};
        w.boxes.push_back(box);
        CylinderSpec disc;  // upright, on a face
        disc.radius = kMinCylinderRadius;
        disc.length = kMinExtent;
        disc.mass = kMinObjectMass;
        disc.position = {0, 0.02, 2 * kMinExtent};
        w.cylinders.push_back(disc);
        CylinderSpec roller = disc;  // lying, on its side
        roller.lying = true;
        roller.length = 2 * kMinCylinderRadius;
        roller.position = {0, 0.03, 2 * kMinCylinderRadius};
        w.cylinders.push_back(roller);

        Simulation sim(w);
        Drive d;
        d.joints = select_joints(sim.world().robots[0].robot, "all");
        d.controller = std::make_shared<Wave>();
        sim.add_drive(0, std::move(d));
        REQUIRE_NOTHROW(sim.run(1));
        const int bodies = static_cast<int>(sim.world().robots[0].robot.bodies.size());
        for (int b = 0; b < bodies; ++b)
            CHECK(finite(sim.body(0, b)));
        // the gait moves the chain by a good part of a module (0.4 of one for boxes) and keeps
        // it on the floor
        const Vec3 moved = sim.robot_displacement(0);
        CHECK(moved.norm() > 0.1 * chain.module.length);
        CHECK(moved.norm() < 20 * chain.module.length);
        // the objects rest on the floor where they should, within 1 %
        REQUIRE(sim.object_count() == 3);
        for (int k = 0; k < 3; ++k)
            CHECK(finite(sim.object(k)));
        CHECK(sim.object(0).pose.position.z == Approx(kMinExtent / 2).epsilon(0.01));
        CHECK(sim.object(1).pose.position.z == Approx(kMinExtent / 2).epsilon(0.01));
        CHECK(sim.object(2).pose.position.z == Approx(kMinCylinderRadius).epsilon(0.01));
    }
}

TEST_CASE("objects that move are at most 300 times as long as their second longest side") {
    WorldSpec w = world_with_robot();
    SECTION("a box") {
        BoxSpec b;
        b.size = {1, 0.003, 0.003};
        b.pose.position = {0, 1, 0.0015};
        b.mass = 1;
        w.boxes.push_back(b);
        require_rejected(w,
                         "box 1 longest side must be at most 300 times its second longest (got 1 "
                         "x 0.003 x 0.003 m: 333.333 times; a static box, of mass 0, may be more "
                         "slender)");
        w.boxes[0].mass = 0;
        CHECK_NOTHROW(validate(w));
        w.boxes[0].mass = 1;
        w.boxes[0].size.y = 0.004;
        CHECK_NOTHROW(validate(w));
    }
    SECTION("a cylinder") {
        CylinderSpec c;
        c.radius = 0.001;
        c.length = 1;
        c.lying = true;
        c.position = {0, 1, 0.001};
        c.mass = 1;
        w.cylinders.push_back(c);
        require_rejected(w,
                         "cylinder 1 length must be at most 300 times its diameter (got 1 m and "
                         "0.002 m: 500 times; a static cylinder, of mass 0, may be more "
                         "slender)");
        w.cylinders[0].mass = 0;
        CHECK_NOTHROW(validate(w));
        w.cylinders[0].mass = 1;
        w.cylinders[0].length = 0.6;
        CHECK_NOTHROW(validate(w));
    }
}

TEST_CASE("bodies at the slenderness bound simulate at the default dt and solver") {
    // chains of 8 bodies 1 m long, 300 times their second longest side (square rods, and strips
    // a tenth as thick), at the lightest and the heaviest mass, under the wave gait with the
    // default and the largest servo torque, bent up and down or sideways: 1 s stays finite
    // (measured: such chains diverge from 700 times at the default dt and solver, free bodies
    // from 10 000 times; docs/formats.md, Limits)
    const double side = 1.0 / kMaxBodySlenderness;
    for (const double thickness : {side, side / 10}) {
        for (const double mass : {kMinBodyMass, kMaxBodyMass}) {
            for (const double torque : {default_servo_def().max_torque, kMaxServoTorque}) {
                for (const Vec3 axis : {Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
                    CAPTURE(thickness, mass, torque, axis.z);
                    WorldSpec w;
                    PlacedRobot placed;
                    placed.robot = test::slender_chain(8, {1, side, thickness}, mass, axis, torque);
                    REQUIRE_NOTHROW(validate(placed.robot));
                    w.robots.push_back(std::move(placed));
                    Simulation sim(w);
                    Drive d;
                    d.joints = select_joints(sim.world().robots[0].robot, "all");
                    d.controller = std::make_shared<Wave>();
                    sim.add_drive(0, std::move(d));
                    REQUIRE_NOTHROW(sim.run(1));
                    for (int b = 0; b < 8; ++b)
                        CHECK(finite(sim.body(0, b)));
                }
            }
        }
    }
    // a box and a cylinder at the bound that move, dropped turned onto the floor
    for (const double mass : {kMinObjectMass, kMaxObjectMass}) {
        CAPTURE(mass);
        WorldSpec w;
        BoxSpec box;
        box.size = {1, side, side / 10};
        box.mass = mass;
        box.pose.position = {0, 0, 0.5};
        const Vec3 tilt{1, 2, 0.5};
        box.pose.orientation = Quat::from_axis_angle(tilt * (1 / tilt.norm()), 0.5);
        w.boxes.push_back(box);
        CylinderSpec rod;
        rod.radius = 0.5 / kMaxBodySlenderness;
        rod.length = 1;
        rod.lying = true;
        rod.yaw = 0.3;
        rod.position = {0, 1, 0.2};
        rod.mass = mass;
        w.cylinders.push_back(rod);
        Simulation sim(w);
        REQUIRE_NOTHROW(sim.run(1));
        CHECK(finite(sim.object(0)));
        CHECK(finite(sim.object(1)));
    }
}

TEST_CASE("heightfield heights are within 1000 m") {
    WorldSpec w = world_with_robot();
    HeightfieldSpec h;
    h.samples_x = 2;
    h.samples_y = 2;
    h.heights = {0, 0, 1e6, 0};
    w.heightfields.push_back(h);
    require_rejected(w,
                     "heightfield 1 height at grid point (1, 2) must be in [-1000, 1000] m "
                     "(got 1000000)");
    w.heightfields[0].heights[2] = -HUGE_VAL;
    require_rejected(w, "heightfield 1 height at grid point (1, 2) must be a finite number");
    w.heightfields[0].heights[2] = -1000;
    CHECK_NOTHROW(validate(w));
    w.heightfields[0].heights.clear();
    w.heightfields[0].image = "x.png";
    w.heightfields[0].max_height = 2000;
    require_rejected(w, "heightfield 1 max_height must be at most 1000 m (got 2000 m)");
}

TEST_CASE("a world's objects are bounded in number") {
    WorldSpec w = world_with_robot();
    // 1e8 stones: each field within its own limit, together far beyond the world's
    RubbleSpec r;
    r.count = kMaxRubbleCount;
    w.rubble.assign(1000, r);
    CHECK(solid_count(w) == 100000000);
    require_rejected(w,
                     "the world's objects make 100000000 rigid bodies (at most 250000: fewer "
                     "stones, steps or objects)");
    w.rubble.resize(2);
    CHECK_NOTHROW(validate(w));
    SECTION("heightfields, whose samples add up") {
        w.rubble.clear();
        HeightfieldSpec h;
        h.samples_x = h.samples_y = kMaxHeightfieldSide;
        h.heights.assign(static_cast<size_t>(kMaxHeightSamples), 0.0);
        w.heightfields = {h};
        CHECK_NOTHROW(validate(w));
        w.heightfields.push_back(h);
        require_rejected(w,
                         "the world's heightfields have 33554432 samples together (at most "
                         "16777216)");
    }
    SECTION("robots") {
        w.rubble.clear();
        w.robots.resize(kMaxRobots + 1, w.robots[0]);
        require_rejected(w, "a world holds at most 1000 robots (got 1001)");
    }
}

TEST_CASE("the robots of a world are validated") {
    WorldSpec w = world_with_robot();
    w.robots[0].robot.bodies[2].mass = 0;
    require_rejected(w, "robot 'snake' body 'head' mass must be positive (got 0 kg)");
}

TEST_CASE("every object of the world library is checked, named by kind and number") {
    WorldSpec w = world_with_robot();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    SECTION("walls") {
        w.walls.resize(2);
        REQUIRE_NOTHROW(validate(w));
        w.walls[1].thickness = -0.01;
        require_rejected(w, "wall 2 thickness must be positive (got -0.01 m)");
        w.walls[1].thickness = 0.01;
        w.walls[0].yaw = nan;
        require_rejected(w, "wall 1 yaw must be a finite number");
    }
    SECTION("ramps") {
        w.ramps.resize(1);
        REQUIRE_NOTHROW(validate(w));
        w.ramps[0].slope = deg_to_rad(95);
        require_rejected(w,
                         "ramp 1 slope must be between 0 and 90 deg, both excluded (got 95 deg)");
        w.ramps[0].slope = 0;
        require_rejected(w, "ramp 1 slope must be between 0 and 90 deg, both excluded (got 0 deg)");
        w.ramps[0].slope = nan;
        require_rejected(w, "ramp 1 slope must be between 0 and 90 deg, both excluded (got nan)");
        w.ramps[0].slope = 0.2;
        w.ramps[0].friction = 1.01;
        require_rejected(w, "ramp 1 friction must be in [0, 1] (got 1.01)");
    }
    SECTION("stairs") {
        w.stairs.resize(2);
        w.stairs[1].step_height = -0.01;
        require_rejected(w, "stairs 2 step_height must be positive (got -0.01 m)");
        w.stairs[1].step_height = 0.01;
        w.stairs[1].steps = 0;
        require_rejected(w, "stairs 2 steps must be in [1, 1000] (got 0)");
        w.stairs[1].steps = 2;
        w.stairs[0].landing = -1;
        require_rejected(w, "stairs 1 landing must not be negative (got -1 m)");
    }
    SECTION("cylinders") {
        w.cylinders.resize(1);
        w.cylinders[0].mass = -2;
        require_rejected(w, "cylinder 1 mass must not be negative (got -2 kg)");
        w.cylinders[0].mass = 2;
        w.cylinders[0].radius = 0;
        require_rejected(w, "cylinder 1 radius must be positive (got 0 m)");
    }
    SECTION("pipes") {
        w.pipes.resize(1);
        w.pipes[0].sides = 2;
        require_rejected(w, "pipe 1 sides must be in [3, 256] (got 2)");
        w.pipes[0].sides = 8;
        w.pipes[0].position.y = std::numeric_limits<double>::infinity();
        require_rejected(w, "pipe 1 position y must be a finite number");
    }
    SECTION("rubble") {
        w.rubble.resize(1);
        w.rubble[0].max_size = 0.01;
        require_rejected(w, "rubble 1 max_size must not be below min_size (got 0.01 < 0.02 m)");
        w.rubble[0].max_size = 0.05;
        w.rubble[0].count = -1;
        require_rejected(w, "rubble 1 count must be in [0, 100000] (got -1)");
        w.rubble[0].count = 0;
        CHECK_NOTHROW(validate(w));
        w.rubble[0].friction = -0.5;
        require_rejected(w, "rubble 1 friction must be in [0, 1] (got -0.5)");
    }
    SECTION("heightfields") {
        w.heightfields.resize(1);
        require_rejected(w, "heightfield 1 needs heights or an image");
        HeightfieldSpec& h = w.heightfields[0];
        h.samples_x = 2;
        h.samples_y = 3;
        h.heights = {0, 0, 0, 0, 0};
        require_rejected(w, "heightfield 1 needs samples_x · samples_y = 6 heights (got 5)");
        h.heights.push_back(nan);
        require_rejected(w, "heightfield 1 height at grid point (2, 3) must be a finite number");
        h.heights.back() = 0.1;
        CHECK_NOTHROW(validate(w));
        h.samples_x = 1;
        h.heights.resize(3);
        require_rejected(w, "heightfield 1 samples_x must be in [2, 4096] (got 1)");
        h.image = "x.png";
        require_rejected(w, "heightfield 1 has both heights and an image (give one)");
        h.heights.clear();
        h.max_height = 0;
        require_rejected(w, "heightfield 1 max_height must be positive (got 0 m)");
        // validation does not read the image; compiling does
        h.max_height = 0.1;
        h.image = "/tmp/gaitlab_no_such_dir/x.png";
        CHECK_NOTHROW(validate(w));
        REQUIRE_THROWS_WITH(
            Simulation(w),
            Equals("heightfield 1 cannot read image '/tmp/gaitlab_no_such_dir/x.png': no such "
                   "file or directory"));
    }
    SECTION("a robot's placement") {
        w.robots[0].pose.position.x = nan;
        require_rejected(w, "robot 'snake' position x must be a finite number");
        w.robots[0].pose.position.x = 0;
        w.robots[0].pose.orientation = {2, 0, 0, 0};
        require_rejected(w, "robot 'snake' orientation must be a unit quaternion");
    }
}
