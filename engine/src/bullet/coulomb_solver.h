// The constraint solver of every gaitlab world: Bullet's sequential impulse solver with the
// contact model of docs/architecture.md ("Contact model"). Header-only so that the raw Bullet
// baseline of the benchmarks (bench/raw_bullet_loop.cpp) steps exactly the engine's physics.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <tuple>
#include <vector>

namespace gaitlab {

// The contact model: Coulomb friction where a contact slides, a static constraint where it
// does not (docs/architecture.md, "Contact model"). Bullet's solver gives each contact one
// friction row (along the slip, or an arbitrary axis at rest: a robot at rest creeps along
// the other) or, with SOLVER_USE_2_FRICTION_DIRECTIONS, two rows each bounded by μN on its
// own (a friction pyramid: a sliding contact then gets up to √2 μN, up to 45° off the slip).
// Here each contact chooses: if its tangential slip speed at the start of the step exceeds
// kSlideSpeed it gets one row along the slip, bounded by μN (Coulomb: |f| ≤ μN against the
// slip); if not, it gets two rows along fixed axes of its normal, which hold it at rest.
// Everything else is Bullet's own set-up (setupContactConstraint, addFrictionConstraint);
// rolling, spinning and anisotropic friction, which gaitlab never sets, are left out.
// Bullet 3.24 does not warm-start friction rows, and neither does this; the directions are
// stored in the manifold point (m_lateralFrictionDir1/2), which a clone copies.
inline constexpr btScalar kSlideSpeed = btScalar(0.001);  // m/s

// The collision configuration of every gaitlab world: Bullet's default, except that a box on a
// plane (a module on the floor) gets the corners of its whole face or edge on the floor. By
// default Bullet adds one point per step, the deepest corner, to the points the pair's manifold
// kept from earlier steps, so which corners of a face are held (one to four) depends on the
// history of rounding: asymmetric contact sets that made a planar gait drift sideways (a 2-module
// pitch-pitch robot by 0.1-16 % of its travel, depending on dt and iterations) and its speed
// depend on the settings (docs/performance.md, "Convergence"). With this, while a pair holds
// fewer than 4 points, each step also looks for the deepest corner of the box tilted by 22.5
// degrees about 6 axes of the plane (Bullet's multipoint collision), which finds the other
// corners of the face; each corner found is a point at its true place and depth. (With 4 axes,
// or below 3 points only, an undriven 8-module pitch-yaw robot crept 0.21-0.27 mm in 20 s,
// where the issue asks < 0.2 mm; with 6, 0.015-0.018 mm.)
class ContactConfiguration : public btDefaultCollisionConfiguration {
  public:
    ContactConfiguration() { setPlaneConvexMultipointIterations(6, 4); }
};

class CoulombSolver : public btSequentialImpulseConstraintSolver {
  public:
    // Solves the contacts and joints of a group in an order of their own (by the bodies'
    // user indices, then the contact's parts; joints by their user constraint id), not in the
    // order Bullet hands them over. Bullet's order comes from an unstable sort by simulation
    // island of every manifold the dispatcher holds, empty ones included, and islands are
    // merged by every pair of the broadphase, including pairs whose bounding boxes no longer
    // overlap but which its incremental clean-up has not reached yet. So it depends on the
    // broadphase's history, which a world rebuilt by PhysicsWorld::copy_state_from does not
    // share with one that was never rebuilt: a clone and its original would agree with each
    // other but not with a twin that was never cloned. Each contact's and joint's rows depend
    // only on its bodies, so solving groups together or apart gives the same bits once the
    // order within each group is fixed.
    btScalar solveGroup(btCollisionObject** bodies, int body_count,
                        btPersistentManifold** manifolds, int manifold_count,
                        btTypedConstraint** constraints, int constraint_count,
                        const btContactSolverInfo& info, btIDebugDraw* draw,
                        btDispatcher* dispatcher) override {
        sorted_manifolds_.assign(manifolds, manifolds + manifold_count);
        std::stable_sort(sorted_manifolds_.begin(), sorted_manifolds_.end(),
                         [](const btPersistentManifold* x, const btPersistentManifold* y) {
                             return key(*x) < key(*y);
                         });
        sorted_constraints_.assign(constraints, constraints + constraint_count);
        std::stable_sort(sorted_constraints_.begin(), sorted_constraints_.end(),
                         [](const btTypedConstraint* x, const btTypedConstraint* y) {
                             return x->getUserConstraintId() < y->getUserConstraintId();
                         });
        return btSequentialImpulseConstraintSolver::solveGroup(
            bodies, body_count, sorted_manifolds_.data(), manifold_count,
            sorted_constraints_.data(), constraint_count, info, draw, dispatcher);
    }

  protected:
    void convertContacts(btPersistentManifold** manifolds, int count,
                         const btContactSolverInfo& info) override {
        for (int i = 0; i < count; ++i)
            convert(*manifolds[i], info);
    }

    btScalar solveGroupCacheFriendlyFinish(btCollisionObject** bodies, int count,
                                           const btContactSolverInfo& info) override {
        // the friction impulse of each contact along its directions, for contacts(): Bullet's
        // own write-back (without SOLVER_USE_2_FRICTION_DIRECTIONS) keeps only the first row's
        for (int k = 0; k < m_tmpSolverContactConstraintPool.size(); ++k) {
            const btSolverConstraint& c = m_tmpSolverContactConstraintPool[k];
            auto* point = static_cast<btManifoldPoint*>(c.m_originalContactPoint);
            const int first = c.m_frictionIndex;
            const int rows = m_tmpSolverContactFrictionConstraintPool.size();
            point->m_appliedImpulseLateral1 =
                m_tmpSolverContactFrictionConstraintPool[first].m_appliedImpulse;
            const bool two =
                first + 1 < rows &&
                m_tmpSolverContactFrictionConstraintPool[first + 1].m_frictionIndex == k;
            point->m_appliedImpulseLateral2 =
                two ? m_tmpSolverContactFrictionConstraintPool[first + 1].m_appliedImpulse : 0;
        }
        return btSequentialImpulseConstraintSolver::solveGroupCacheFriendlyFinish(bodies, count,
                                                                                  info);
    }

  private:
    // a manifold's place: its bodies, then the parts of a compound or triangle mesh its points
    // are on (one manifold per child of a compound); empty manifolds add no rows
    static std::tuple<int, int, int, int, int, int, int> key(const btPersistentManifold& m) {
        const int n = m.getNumContacts();
        if (n == 0)
            return {0, m.getBody0()->getUserIndex(), m.getBody1()->getUserIndex(), 0, 0, 0, 0};
        const btManifoldPoint& p = m.getContactPoint(0);
        return {1,
                m.getBody0()->getUserIndex(),
                m.getBody1()->getUserIndex(),
                p.m_index0,
                p.m_index1,
                p.m_partId0,
                p.m_partId1};
    }

    std::vector<btPersistentManifold*> sorted_manifolds_;
    std::vector<btTypedConstraint*> sorted_constraints_;

    void convert(btPersistentManifold& manifold, const btContactSolverInfo& info) {
        // Bullet's solver takes non-const bodies; it changes only their solver data
        auto* a = const_cast<btCollisionObject*>(manifold.getBody0());
        auto* b = const_cast<btCollisionObject*>(manifold.getBody1());
        const int ia = getOrInitSolverBody(*a, info.m_timeStep);
        const int ib = getOrInitSolverBody(*b, info.m_timeStep);
        const btSolverBody& sa = m_tmpSolverBodyPool[ia];
        const btSolverBody& sb = m_tmpSolverBodyPool[ib];
        if (sa.m_invMass.fuzzyZero() && sb.m_invMass.fuzzyZero()) return;  // two fixed bodies
        for (int j = 0; j < manifold.getNumContacts(); ++j) {
            btManifoldPoint& cp = manifold.getContactPoint(j);
            if (cp.getDistance() > manifold.getContactProcessingThreshold()) continue;
            const int index = m_tmpSolverContactConstraintPool.size();
            btSolverConstraint& contact = m_tmpSolverContactConstraintPool.expandNonInitializing();
            contact.m_solverBodyIdA = ia;
            contact.m_solverBodyIdB = ib;
            contact.m_originalContactPoint = &cp;
            const btVector3 rel_a = cp.getPositionWorldOnA() - a->getWorldTransform().getOrigin();
            const btVector3 rel_b = cp.getPositionWorldOnB() - b->getWorldTransform().getOrigin();
            btVector3 va, vb;
            sa.getVelocityInLocalPointNoDelta(rel_a, va);
            sb.getVelocityInLocalPointNoDelta(rel_b, vb);
            const btVector3& n = cp.m_normalWorldOnB;
            const btVector3 slip = (va - vb) - n * n.dot(va - vb);  // of A relative to B
            btScalar relaxation;
            setupContactConstraint(contact, ia, ib, cp, info, relaxation, rel_a, rel_b);
            contact.m_frictionIndex = m_tmpSolverContactFrictionConstraintPool.size();
            const btScalar speed2 = slip.length2();
            if (speed2 > kSlideSpeed * kSlideSpeed) {
                cp.m_lateralFrictionDir1 = slip / btSqrt(speed2);
                cp.m_lateralFrictionDir2 = cp.m_lateralFrictionDir1.cross(n);
                addFrictionConstraint(cp.m_lateralFrictionDir1, ia, ib, index, cp, rel_a, rel_b, a,
                                      b, relaxation, info);
            } else {
                btPlaneSpace1(n, cp.m_lateralFrictionDir1, cp.m_lateralFrictionDir2);
                addFrictionConstraint(cp.m_lateralFrictionDir1, ia, ib, index, cp, rel_a, rel_b, a,
                                      b, relaxation, info);
                addFrictionConstraint(cp.m_lateralFrictionDir2, ia, ib, index, cp, rel_a, rel_b, a,
                                      b, relaxation, info);
            }
        }
    }
};

}  // namespace gaitlab
