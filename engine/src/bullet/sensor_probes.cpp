#include "bullet/sensor_probes.h"

#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <btBulletDynamicsCommon.h>

#include "bullet/physics_world.h"

namespace gaitlab {

namespace {

btVector3 to_bt(const Vec3& v) {
    return {static_cast<btScalar>(v.x), static_cast<btScalar>(v.y), static_cast<btScalar>(v.z)};
}

}  // namespace

RayHit cast_ray(const PhysicsWorld& physics, int body, const Vec3& origin, const Vec3& direction,
                double max_range) {
    const btVector3 from = to_bt(origin);
    const btVector3 to = to_bt(origin + direction * max_range);
    btCollisionWorld::ClosestRayResultCallback cb(from, to);
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
    RayHit h;
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
            if (want_a) {
                const btVector3& l = p.m_localPointA;
                out.push_back({a, {l.x(), l.y(), l.z()}, impulse});
            }
            if (want_b) {
                const btVector3& l = p.m_localPointB;
                out.push_back({b, {l.x(), l.y(), l.z()}, impulse});
            }
        }
    }
}

}  // namespace gaitlab
