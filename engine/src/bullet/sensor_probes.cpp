#include "bullet/sensor_probes.h"

#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>
#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <btBulletDynamicsCommon.h>

#include <cmath>

#include "bullet/box_heightfield.h"
#include "bullet/physics_world.h"

namespace gaitlab {

namespace {

btVector3 to_bt(const Vec3& v) {
    return {static_cast<btScalar>(v.x), static_cast<btScalar>(v.y), static_cast<btScalar>(v.z)};
}

bool contains(const btCollisionShape& shape, const btTransform& at, const btVector3& p);

// whether `q` (in the compound's frame) lies in one of its children: only the children whose
// bounding boxes hold it are tested, found down the compound's tree (a static compound holds
// every static box of a friction, up to 100 000)
bool compound_contains(const btCompoundShape& compound, const btVector3& q) {
    const btDbvt* tree = compound.getDynamicAabbTree();
    if (!tree) {
        for (int k = 0; k < compound.getNumChildShapes(); ++k) {
            if (contains(*compound.getChildShape(k), compound.getChildTransform(k), q)) return true;
        }
        return false;
    }
    // depth first; the stack holds at most the tree's depth + 1 nodes, and the tree stays
    // shallow (physics_world.cpp inserts the children in shuffled order: about 50 levels for
    // 100 000). A path deeper than the stack would be cut short, missing a child
    constexpr int kStack = 128;
    const btDbvtNode* stack[kStack];
    int n = 0;
    if (tree->m_root) stack[n++] = tree->m_root;
    while (n > 0) {
        const btDbvtNode* node = stack[--n];
        if (!Intersect(node->volume, q)) continue;
        if (node->isleaf()) {
            const int k = node->dataAsInt;
            if (contains(*compound.getChildShape(k), compound.getChildTransform(k), q)) return true;
        } else if (n + 2 <= kStack) {
            stack[n++] = node->childs[0];
            stack[n++] = node->childs[1];
        }
    }
    return false;
}

// whether `q` (in the heightfield's frame) lies under its surface, over its grid and no lower
// than its lowest sample: the part of space its collider pushes a box out of
bool heightfield_contains(const HeightfieldShape& field, const btVector3& q) {
    btVector3 lo, hi;
    field.getAabb(btTransform::getIdentity(), lo, hi);
    btVector3 a, n;
    return q.z() >= lo.z() && HeightfieldGrid(field).triangle_under(q, a, n) && (q - a).dot(n) <= 0;
}

// whether `p` (world frame) lies inside `shape` placed at `at`, or on its surface. Exact for the
// shapes a gaitlab world is made of (boxes, cylinders, the floor's plane, heightfields,
// compounds of them); any other convex shape (a ramp's hull) is asked of GJK
bool contains(const btCollisionShape& shape, const btTransform& at, const btVector3& p) {
    const btVector3 q = at.invXform(p);
    switch (shape.getShapeType()) {
        case BOX_SHAPE_PROXYTYPE: {
            const btVector3 h = static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin();
            return std::abs(q.x()) <= h.x() && std::abs(q.y()) <= h.y() && std::abs(q.z()) <= h.z();
        }
        case CYLINDER_SHAPE_PROXYTYPE: {
            const auto& c = static_cast<const btCylinderShape&>(shape);
            const int axis = c.getUpAxis();
            const btScalar r = c.getRadius();
            return std::abs(q[axis]) <= c.getHalfExtentsWithMargin()[axis] &&
                   q.length2() - q[axis] * q[axis] <= r * r;
        }
        case STATIC_PLANE_PROXYTYPE: {
            const auto& plane = static_cast<const btStaticPlaneShape&>(shape);
            return q.dot(plane.getPlaneNormal()) <= plane.getPlaneConstant();
        }
        case TERRAIN_SHAPE_PROXYTYPE: {
            const auto* field = dynamic_cast<const HeightfieldShape*>(&shape);
            return field && heightfield_contains(*field, q);
        }
        case COMPOUND_SHAPE_PROXYTYPE:
            return compound_contains(static_cast<const btCompoundShape&>(shape), q);
        default:
            break;
    }
    if (!shape.isConvex()) return false;
    // the distance from the shape without its margin to a point (a sphere of radius 0)
    const auto& convex = static_cast<const btConvexShape&>(shape);
    const btSphereShape point(0);
    btGjkEpaSolver2::sResults r;
    if (btGjkEpaSolver2::Distance(&convex, at, &point, btTransform(btQuaternion::getIdentity(), p),
                                  btVector3(1, 1, 1), r)) {
        return r.distance <= convex.getMargin();
    }
    return r.status == btGjkEpaSolver2::sResults::Penetrating;
}

// Bullet's closest-hit ray callback that also notes whether the ray's origin lies inside one of
// the objects it may hit. Bullet's ray test asks needsCollision of every object whose bounding
// box the ray crosses, which includes every box that holds the origin, before it casts the ray
// at the object: so the origin is tested against only the objects the ray visits anyway, and
// the ray's own answer is unchanged
struct OriginRayCallback : btCollisionWorld::ClosestRayResultCallback {
    using ClosestRayResultCallback::ClosestRayResultCallback;
    mutable bool origin_inside = false;

    bool needsCollision(btBroadphaseProxy* proxy) const override {
        if (!ClosestRayResultCallback::needsCollision(proxy)) return false;
        // most objects a long ray crosses are far from its origin: their bounding boxes
        // (which hold the object with a margin) leave them out at once
        if (!origin_inside &&
            TestPointAgainstAabb2(proxy->m_aabbMin, proxy->m_aabbMax, m_rayFromWorld)) {
            const auto* o = static_cast<const btCollisionObject*>(proxy->m_clientObject);
            origin_inside =
                contains(*o->getCollisionShape(), o->getWorldTransform(), m_rayFromWorld);
        }
        return true;
    }
};

}  // namespace

RayHit cast_ray(const PhysicsWorld& physics, int body, const Vec3& origin, const Vec3& direction,
                double max_range) {
    const btVector3 from = to_bt(origin);
    const btVector3 to = to_bt(origin + direction * max_range);
    OriginRayCallback cb(from, to);
    // the ray belongs to the robot's collision group and skips it: a robot's bodies all share
    // one group bit (physics_world.cpp)
    const btBroadphaseProxy* proxy = physics.bullet_body(body).getBroadphaseHandle();
    cb.m_collisionFilterGroup = proxy->m_collisionFilterGroup;
    cb.m_collisionFilterMask = btBroadphaseProxy::AllFilter & ~proxy->m_collisionFilterGroup;
    // Bullet's default ray-convex test (btSubsimplexConvexCast) is approximate: against a box
    // it may stop up to about 2 mm short, depending on the last bits of the ray's origin, so
    // a sensor at rest would read a distance that flickers between two values. The GJK cast
    // hits the face within a micrometre
    cb.m_flags |= btTriangleRaycastCallback::kF_UseGjkConvexCastRaytest;
    physics.bullet_world().rayTest(from, to, cb);
    // a ray that starts inside something (a module pushed into a box or sunk into the floor)
    // is blocked where it starts, as a real range finder pressed against a wall reads its
    // minimum; Bullet's ray sees a surface from inside no more than from outside
    RayHit h;
    if (cb.origin_inside) {
        h.hit = true;
        h.distance = 0;
        return h;
    }
    h.hit = cb.hasHit();
    h.distance = h.hit ? static_cast<double>(cb.m_closestHitFraction) * max_range : max_range;
    return h;
}

void mark_robot_bodies(PhysicsWorld& physics, int robot_bodies) {
    // the third user index of Bullet's collision objects holds the global body index (-1, the
    // default, for everything that is not a robot body)
    for (int b = 0; b < robot_bodies; ++b)
        physics.bullet_body(b).setUserIndex3(b);
}

void collect_contacts(const PhysicsWorld& physics, const std::vector<char>& wanted,
                      std::vector<BodyContact>& out) {
    btDispatcher& d = *physics.bullet_world().getDispatcher();
    const int n = d.getNumManifolds();
    for (int i = 0; i < n; ++i) {
        const btPersistentManifold& m = *d.getManifoldByIndexInternal(i);
        const int a = m.getBody0()->getUserIndex3();
        const int b = m.getBody1()->getUserIndex3();
        const bool want_a = a >= 0 && wanted[static_cast<size_t>(a)];
        const bool want_b = b >= 0 && wanted[static_cast<size_t>(b)];
        if (!want_a && !want_b) continue;
        for (int k = 0; k < m.getNumContacts(); ++k) {
            const btManifoldPoint& p = m.getContactPoint(k);
            if (p.getDistance() > btScalar(kTouchDistance)) continue;
            const double impulse = p.getAppliedImpulse();
            // Bullet's local points are from the body's centre of mass; the engine's body frame
            // is its shape's, the offset behind
            if (want_a) {
                const btVector3& l = p.m_localPointA;
                out.push_back({a, Vec3{l.x(), l.y(), l.z()} + physics.center_of_mass(a), impulse});
            }
            if (want_b) {
                const btVector3& l = p.m_localPointB;
                out.push_back({b, Vec3{l.x(), l.y(), l.z()} + physics.center_of_mass(b), impulse});
            }
        }
    }
}

}  // namespace gaitlab
