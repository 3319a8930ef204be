// Tests for engine/src/world.cpp: world spec validation (directly and through Simulation).
#include "gaitlab/world.h"

#include <catch2/catch.hpp>

#include <limits>

#include "gaitlab/error.h"
#include "gaitlab/simulation.h"

using namespace gaitlab;
using Catch::Matchers::Equals;

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
}

TEST_CASE("gravity must be finite") {
    WorldSpec w = world_with_robot();
    w.gravity.x = std::numeric_limits<double>::quiet_NaN();
    require_rejected(w, "gravity x must be a finite number");
}

TEST_CASE("the robots of a world are validated") {
    WorldSpec w = world_with_robot();
    w.robots[0].robot.bodies[2].mass = 0;
    require_rejected(w, "robot 'snake' body 'head' mass must be positive (got 0 kg)");
}
