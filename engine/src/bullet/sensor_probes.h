// What the sensors ask of Bullet: a ray cast and the contact points of the last step. This
// interface speaks gaitlab types; engine/src/sim/sensing.cpp turns the answers into readings.
#pragma once

#include <vector>

#include "gaitlab/types.h"

namespace gaitlab {

class PhysicsWorld;

/// Where a ray first meets something.
struct RayHit {
    bool hit = false;
    double distance = 0;  ///< m from the ray's origin; max_range when nothing is hit
};

/// Casts a ray from `origin` along the unit vector `direction` (world frame) up to `max_range`
/// m. The bodies of the robot that `body` belongs to are transparent to it (the sensor sees
/// out of its own robot); everything else stops it: floor, boxes, other robots. A ray whose
/// origin lies inside one of those, or on its surface, stops there: a hit at distance 0.
RayHit cast_ray(const PhysicsWorld& physics, int body, const Vec3& origin, const Vec3& direction,
                double max_range);

/// One contact point on a robot body.
struct BodyContact {
    int body;        ///< global body index
    Vec3 local;      ///< the point in that body's frame, m
    double impulse;  ///< normal impulse the solver applied at it in the last step, N·s
};

/// Points within kTouchDistance of each other count as touching.
constexpr double kTouchDistance = 0.001;  // m

/// Marks the bodies 0 .. robot_bodies - 1 of `physics` as robot bodies for collect_contacts
/// (once per physics world).
void mark_robot_bodies(PhysicsWorld& physics, int robot_bodies);

/// Appends to `out` every touching contact point of the last step on a robot body b with
/// wanted[b] != 0 (both sides of a contact between two such bodies).
void collect_contacts(const PhysicsWorld& physics, const std::vector<char>& wanted,
                      std::vector<BodyContact>& out);

}  // namespace gaitlab
