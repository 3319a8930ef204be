// What the engine's two box colliders (box_plane.h, box_heightfield.h) share: the one manifold a
// box and the other shape hold, Bullet's algorithm interface around it, and making the algorithm
// in the dispatcher's memory. A collider derives from BoxCollider<Itself, OtherShape> and says
// which points the pair touches at (its collide()).
#pragma once

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <utility>

namespace gaitlab {

// `Collider` (CRTP), for a btBoxShape and an `Other` shape, has a member
//   void collide(const btBoxShape* box, const btTransform& box_at, const Other* other,
//                const btTransform& other_at, btScalar reach, btManifoldResult* out);
// that adds the pair's contact points to `out` (whose manifold is manifold_): every point closer
// than `reach` (m), the manifold's breaking threshold and the dispatcher's closest-point
// distance. The base refreshes the manifold's points afterwards, and gives a box whose
// transform is not finite no points without asking collide().
template <typename Collider, typename Other>
class BoxCollider : public btCollisionAlgorithm {
  public:
    // `swapped`: w0 is the other shape and w1 the box (else w0 the box)
    BoxCollider(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* w0,
                const btCollisionObjectWrapper* w1, bool swapped)
        : btCollisionAlgorithm(ci), swapped_(swapped) {
        const btCollisionObject* box = (swapped ? w1 : w0)->getCollisionObject();
        const btCollisionObject* other = (swapped ? w0 : w1)->getCollisionObject();
        if (m_dispatcher->needsCollision(box, other)) {
            manifold_ = m_dispatcher->getNewManifold(box, other);
        }
    }
    ~BoxCollider() override {
        if (manifold_) m_dispatcher->releaseManifold(manifold_);
    }
    BoxCollider(const BoxCollider&) = delete;
    BoxCollider& operator=(const BoxCollider&) = delete;

    void processCollision(const btCollisionObjectWrapper* w0, const btCollisionObjectWrapper* w1,
                          const btDispatcherInfo&, btManifoldResult* out) final {
        if (!manifold_) return;
        const btCollisionObjectWrapper& box = swapped_ ? *w1 : *w0;
        const btCollisionObjectWrapper& other = swapped_ ? *w0 : *w1;
        const btTransform& box_at = box.getWorldTransform();
        // a box that is not finite (the step before a diverged simulation is stopped) touches
        // nothing: its depths would be NaN or infinite, and a point at -inf would stay
        if (!is_finite(box_at)) {
            manifold_->clearManifold();
            return;
        }
        const btScalar reach =
            manifold_->getContactBreakingThreshold() + out->m_closestPointDistanceThreshold;
        out->setPersistentManifold(manifold_);
        static_cast<Collider*>(this)->collide(
            static_cast<const btBoxShape*>(box.getCollisionShape()), box_at,
            static_cast<const Other*>(other.getCollisionShape()), other.getWorldTransform(), reach,
            out);
        if (manifold_->getNumContacts()) out->refreshContactPoints();
    }

    btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                   btManifoldResult*) final {
        return btScalar(1);
    }

    void getAllContactManifolds(btManifoldArray& manifolds) final {
        if (manifold_) manifolds.push_back(manifold_);
    }

    /// What a collision configuration hands out for the pair: makes the algorithm with
    /// `Collider::create(ci, w0, w1, swapped, setting)`.
    template <typename Setting>
    struct CreateFunc : public btCollisionAlgorithmCreateFunc {
        Setting setting{};
        btCollisionAlgorithm* CreateCollisionAlgorithm(
            btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* w0,
            const btCollisionObjectWrapper* w1) override {
            return Collider::create(ci, w0, w1, m_swapped, setting);
        }
    };

    /// The algorithm for a pair: a new `Collider(ci, w0, w1, swapped, setting)`; a collider
    /// hides this with its own create() when it needs more.
    template <typename Setting>
    static btCollisionAlgorithm* create(btCollisionAlgorithmConstructionInfo& ci,
                                        const btCollisionObjectWrapper* w0,
                                        const btCollisionObjectWrapper* w1, bool swapped,
                                        const Setting& setting) {
        return make(ci, w0, w1, swapped, setting);
    }

    /// A new `Collider(ci, args...)` in the dispatcher's memory for algorithms, as a
    /// btCollisionAlgorithmCreateFunc returns it (the dispatcher destroys and frees it).
    template <typename... Args>
    static btCollisionAlgorithm* make(btCollisionAlgorithmConstructionInfo& ci, Args&&... args) {
        void* mem = ci.m_dispatcher1->allocateCollisionAlgorithm(sizeof(Collider));
        return new (mem) Collider(ci, std::forward<Args>(args)...);
    }

  protected:
    btPersistentManifold* manifold_ = nullptr;
    bool swapped_;

  private:
    // whether every number of `t` is finite: their sum is not if one is NaN or infinite (or if
    // they are beyond 1e38 m, which no scene reaches)
    static bool is_finite(const btTransform& t) {
        const btMatrix3x3& r = t.getBasis();
        const btVector3& o = t.getOrigin();
        btScalar sum = o.x() + o.y() + o.z();
        for (int i = 0; i < 3; ++i)
            sum += r[i].x() + r[i].y() + r[i].z();
        return std::isfinite(sum);
    }
};

}  // namespace gaitlab
