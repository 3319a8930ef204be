// The constraint solver of every gaitlab world: Bullet's sequential impulse solver with the
// contact model of docs/architecture.md ("Contact model"). Header-only so that the raw Bullet
// baseline of the benchmarks (bench/raw_bullet_loop.cpp) steps exactly the engine's physics.
#pragma once

#include <btBulletDynamicsCommon.h>

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

class CoulombSolver : public btSequentialImpulseConstraintSolver {
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
