// The box shape of every gaitlab body and object (physics_world.cpp), and of the benchmarks' raw
// Bullet loop: Bullet's box, whose contact points stay distinct however thin it is. Its one
// function is in box_shape.cpp, the only file that emits its virtual table (and with it
// btBoxShape's inline virtual functions).
#pragma once

#include <btBulletDynamicsCommon.h>

namespace gaitlab {

/// Bullet's btBoxShape with a contact breaking threshold of at most half its smallest side.
///
/// A manifold takes a new contact point for the one it holds within the breaking threshold of
/// it on the box (btPersistentManifold::getCacheEntry), and Bullet makes that threshold 2 % of
/// the shape's bounding radius: 1 % of a long box's length. A box whose smallest side is
/// shorter (1 m by 1 cm, or thinner) had the two corners across that side taken for one point:
/// lying flat on the floor it held only the two corners of one long edge, rolled over onto it
/// and sank until its centre was level with the floor. Half the smallest side keeps every
/// corner its own point; an ordinary box (smallest side above 2 % of its diagonal) keeps
/// Bullet's threshold and every bit of its motion.
class BoxShape : public btBoxShape {
  public:
    /// `half_extents` in m, as btBoxShape takes them.
    explicit BoxShape(const btVector3& half_extents) : btBoxShape(half_extents) {}

    /// Bullet's threshold for `factor`, at most half the smallest side, m.
    btScalar getContactBreakingThreshold(btScalar factor) const override;
};

}  // namespace gaitlab
