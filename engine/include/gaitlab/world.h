// World specs: gravity, floor, objects, and the robots placed in them.
#pragma once

#include <memory>
#include <vector>

#include "gaitlab/actuation.h"
#include "gaitlab/robot.h"
#include "gaitlab/types.h"

namespace gaitlab {

/// An infinite static plane at z = 0.
struct FloorSpec {
    bool enabled = true;
    double friction = 1.0;  ///< in [0, 1]
};

/// A box obstacle. mass = 0 makes it static.
struct BoxSpec {
    Vec3 size{0.1, 0.1, 0.1};  ///< full extents, m, > 0
    Pose pose;                 ///< centre and orientation, world frame
    double mass = 0;           ///< kg, >= 0 (0: static)
    double friction = 1.0;     ///< in [0, 1]
};

/// A robot placed in a world, with the controllers that drive its joint groups.
struct PlacedRobot {
    RobotSpec robot;
    Pose pose;  ///< robot frame in the world frame (identity: tail at the origin, along +x)
    Actuation actuation;
};

/// Everything the physics needs to build a scene.
struct WorldSpec {
    Vec3 gravity{0, 0, -9.81};  ///< m/s²
    FloorSpec floor;
    std::vector<BoxSpec> boxes;
    std::vector<PlacedRobot> robots;
};

/// Checks a world spec (friction ranges, sizes, masses, robots); throws SpecError.
void validate(const WorldSpec& world);

}  // namespace gaitlab
