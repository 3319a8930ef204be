// Tests for controllers/src/offset.cpp: a constant angle per joint, and the turning gait it makes
// with a sine on an overlapping group.
#include "gaitlab/controllers/offset.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <memory>

#include "gaitlab/controllers/sine.h"
#include "gaitlab/simulation.h"
#include "gaitlab/types.h"
#include "rig.h"

using namespace gaitlab;
using gaitlab::test::StillJoints;

namespace {

// lateral displacement (m) of an 8-module pitch-yaw robot after 20 s of a pitch sine with the
// yaw joints held at `offset` degrees
Vec3 pitch_yaw_with_yaw_offset(double offset) {
    ChainSpec chain;
    chain.modules = 8;
    chain.connection = Connection::pitch_yaw;
    PlacedRobot robot{make_chain(chain), {}, {}};
    auto sine = std::make_shared<controllers::Sine>();
    auto hold = std::make_shared<controllers::Offset>();
    hold->set_param("angle", offset);
    robot.actuation.push_back({select_joints(robot.robot, "pitch"), sine});
    robot.actuation.push_back({select_joints(robot.robot, "yaw"), hold});
    WorldSpec world;
    world.floor.friction = 0.8;
    world.robots.push_back(robot);
    Simulation sim(world);
    sim.run(20);
    return sim.robot_displacement(0);
}

}  // namespace

TEST_CASE("offset sets every joint of its group to its angle") {
    controllers::Offset c;
    CHECK(c.param("angle") == 0);
    c.set_param("angle", -30);
    c.bind(3);
    const std::vector<int> joints{0, 1, 2};
    StillJoints reader;
    std::vector<double> targets(3, 1.0);
    ControlIO io(0.03, 0, joints, reader, targets.data());
    c.step(io);
    for (double t : targets)
        CHECK(t == deg_to_rad(-30));
    CHECK_THROWS_WITH(c.set_param("angle", 95), "offset.angle must be in [-90, 90] deg (got 95)");
}

TEST_CASE("a yaw offset on top of a pitch gait turns the robot, the way its sign says") {
    const Vec3 left = pitch_yaw_with_yaw_offset(20);
    const Vec3 straight = pitch_yaw_with_yaw_offset(0);
    const Vec3 right = pitch_yaw_with_yaw_offset(-20);
    CAPTURE(left.x, left.y, straight.x, straight.y, right.x, right.y);
    // straight: along the body axis
    CHECK(std::abs(straight.y) < 0.05 * std::abs(straight.x));
    // a positive (counter-clockwise) yaw bend curves the path towards +y, a negative one to -y
    CHECK(left.y > 0.15);
    CHECK(right.y < -0.15);
    CHECK(std::abs(left.y + right.y) < 0.25 * left.y);
}
