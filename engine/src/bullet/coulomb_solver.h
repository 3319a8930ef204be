// The constraint solver of every gaitlab world: Bullet's sequential impulse solver with the
// contact model of docs/architecture.md ("Contact model"). Header-only so that the raw Bullet
// baseline of the benchmarks (bench/raw_bullet_loop.cpp) steps exactly the engine's physics.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

#include "block_band.h"
#include "newton_step.h"
#include "profile_ldl.h"

namespace gaitlab {

// The contact model: Coulomb friction, |f| <= μN, and where a contact slides f = μN against the
// slip (docs/architecture.md, "Contact model"). Bullet's solver gives each contact one friction
// row (along the slip, or an arbitrary axis at rest: a robot at rest creeps along the other) or,
// with SOLVER_USE_2_FRICTION_DIRECTIONS, two rows each bounded by μN on its own (a friction
// pyramid: a sliding contact then gets up to √2 μN, up to 45° off the slip).
// The engine's model, the friction disk (FrictionModel::disk), gives every contact two rows
// (along the slip where it slides, two fixed axes of its normal where it does not) that the
// solver handles together: in every iteration the pair's impulse is the one that minimises the
// contact's kinetic energy of slip within |f| <= μN (the exact solution for that contact given
// all the others: it stops the slip if that takes at most μN, otherwise it is μN exactly
// against the slip that remains, whichever way the slip turns during the step). A box sliding
// down a ramp accelerates as a = g (sin - μ cos) says within 1 % (engine_physics_world_test).
// The model before it (FrictionModel::per_step, kept for comparisons: bench/dt_terms.cpp)
// chose per contact at the start of each step: one row along the slip, bounded by μN, where the
// contact slid faster than kSlideSpeed; two rows along fixed axes of its normal where it did
// not. That tied a sliding contact's friction to the slip direction of the step's start: a
// contact that stops or turns during the step is frictionless across that direction for the
// whole step, an error of the time step's order (docs/performance.md, "Convergence": the
// pitch-yaw wave of 8 modules 12 % off a converged reference at dt 1 ms, 5 % with the disk),
// and the same box on the ramp accelerated 11-19 % too slowly.
// Everything else is Bullet's own set-up (setupContactConstraint, addFrictionConstraint);
// rolling, spinning and anisotropic friction, which gaitlab never sets, are left out.
// Bullet 3.24 does not warm-start friction rows, and neither does this; the directions are
// stored in the manifold point (m_lateralFrictionDir1/2), which a clone copies.
enum class FrictionModel { per_step, disk };

// How the solver iterates over the rows (docs/performance.md, "Converging the solve"):
// pgs is Bullet's projected Gauss-Seidel, every iteration joints, normals, friction disks in
// the solver's order (CoulombSolver::solveGroup); symmetric alternates that sweep with the
// reverse one (friction disks, normals, joints, each backwards); nncg is pgs with a nonlinear
// conjugate-gradient step after each sweep (Silcowitz, Niebe, Erleben 2010: with d_k the change
// of the rows' impulses in sweep k, beta = |d_k|^2 / |d_k-1|^2, restarted when beta > 1, the
// impulses move by beta p and p becomes beta p + d_k; none after the last sweep, whose
// projections then hold; one beta per set of bodies joined by joints or contacts, split_sets);
// block solves the joints' equality rows (those without bounds: not motors or limits) as one linear
// system, exactly, in each iteration given the impulses of all other rows (J M^-1 J' factored once
// per step, Cholesky on its profile, which for a chain ordered along it is a band: for a chain of
// hinges kept as 5x5 blocks, block_band.h), then the other rows as pgs does; block_nncg is block
// with nncg's step after each sweep (the block's rows among all others).
enum class SolverMethod { pgs, symmetric, nncg, block, block_nncg };

// The three ways the block methods solve K dl = r (CoulombSolver::factor_block, solve_block),
// all taking every sum in the same order, so a chain gives the same bits on each:
// band_fast, a chain of hinges whose bodies are all ordinary rigid bodies with linear and
// angular factors 1 (block_band.h's band_rhs and band_apply); band_generic, a chain with some
// other body (a fixed one, or factors not 1): the generic right side and impulses around
// band_solve; profile, any other structure (a body with three or more hinges, joints whose rows
// do not come in fives): L D L' on K's profile (profile_ldl.h). `automatic` chooses as above.
enum class BlockPath { automatic, band_fast, band_generic, profile };
inline constexpr btScalar kSlideSpeed = btScalar(0.001);  // m/s: slower, the axes are fixed ones
// hinges in a chain from which the block's K is taken in double (CoulombSolver::band_matrix):
// the float entries broke down from about 1200 on a chain lying still; a quarter of that
inline constexpr int kPreciseBand = 256;
// the smallest pivot of the block's factor with K's entries in float, over its row's own
// diagonal, below which K is taken again in double (band_matrix): the rest of the row cancelled
// so much that the entries' float rounding is a large part of the pivot. The standard gaits'
// chains of 2 to 32 y1 modules keep every pivot above 0.17 of its row's; the chains that
// diverged with float entries went to 2e-4 (32 rods of 1 m x 1 cm joined by yaw hinges) and
// 0.03 (128 links of 1 m and 1 kg with 100 N m servos)
inline constexpr double kFloatPivot = 0.05;

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

// One contact's friction impulse (CoulombSolver::solve_friction): for K = [k11 k12; k12 k22]
// the 2x2 matrix that maps the impulses of its two friction rows to their velocities and w the
// slip the contact would have without its friction, the l that minimises 1/2 l'Kl + l'w (the
// kinetic energy of the slip) over |l| <= limit (μN): l = -K^-1 w if that is inside the disk
// (the contact sticks), otherwise l = -(K + g I)^-1 w with g > 0 such that |l| = limit: the
// slip after, w + Kl = -g l, is then exactly against l (Coulomb's law). g comes from Newton's
// method on 1/|l(g)| - 1/limit, nearly linear in g (exactly for an isotropic K), kept within
// the bracket K's eigenvalues give. The solution scales with w and the limit together, so
// where they are so large or so small that the steps' cubes could overflow or underflow (in
// float, Bullet's btScalar here, from 1e13 and below 1e-13), it is taken on them scaled by a
// power of two to about 1, which is exact: the bits are those of the unscaled steps. Always finite
// and within the disk: a slip that is not finite (a diverging world's) gets no impulse.
namespace detail {
inline std::pair<btScalar, btScalar> friction_disk_unscaled(btScalar k11, btScalar k12,
                                                            btScalar k22, btScalar w1, btScalar w2,
                                                            btScalar limit) {
    // l = -(K + g I)^-1 w; returns the determinant of K + g I
    auto impulse = [&](btScalar g, btScalar& l1, btScalar& l2) {
        const btScalar a11 = k11 + g, a22 = k22 + g, d = a11 * a22 - k12 * k12;
        l1 = -(a22 * w1 - k12 * w2) / d;
        l2 = -(a11 * w2 - k12 * w1) / d;
        return d;
    };
    btScalar l1, l2;
    impulse(0, l1, l2);
    // (not <=: a slip that is not a number takes the branch and its fallback)
    if (!(l1 * l1 + l2 * l2 <= limit * limit)) {
        if (limit <= 0) {
            l1 = l2 = 0;
        } else {
            const btScalar wn = btSqrt(w1 * w1 + w2 * w2);
            const btScalar mid = (k11 + k22) / 2;
            const btScalar rad = btSqrt((k11 - k22) * (k11 - k22) / 4 + k12 * k12);
            const btScalar lo = btMax(btScalar(0), wn / limit - (mid + rad));
            const btScalar hi = btMax(lo, wn / limit - (mid - rad));
            btScalar g = (lo + hi) / 2;
            for (int it = 0; it < 6; ++it) {
                const btScalar d = impulse(g, l1, l2);
                const btScalar n2 = l1 * l1 + l2 * l2, len = btSqrt(n2);
                // l'(K + g I)^-1 l, the slope of 1/|l| times |l|^3
                const btScalar q =
                    ((k22 + g) * l1 * l1 - 2 * k12 * l1 * l2 + (k11 + g) * l2 * l2) / d;
                g = btMin(hi, btMax(lo, g - (1 / len - 1 / limit) * n2 * len / q));
            }
            impulse(g, l1, l2);
            // onto the disk (the Newton steps leave |l| within rounding of it)
            const btScalar scale = limit / btSqrt(l1 * l1 + l2 * l2);
            l1 *= scale;
            l2 *= scale;
            // a limit so much smaller than the slip that the steps above overflow (a
            // normal impulse of 1e-30 N s against a slip of 1 m/s), or a slip that is not a
            // number: then the limit against the slip (exact for an isotropic K); 0 where
            // the slip has no direction (0, or not finite)
            if (!(std::isfinite(l1) && std::isfinite(l2))) {
                const btScalar length =
                    wn > 0 && std::isfinite(wn) ? wn : btScalar(std::hypot(w1, w2));
                const bool direction = length > 0 && std::isfinite(length);
                l1 = direction ? -w1 / length * limit : 0;
                l2 = direction ? -w2 / length * limit : 0;
            }
        }
    }
    return {l1, l2};
}
}  // namespace detail

inline std::pair<btScalar, btScalar> friction_disk(btScalar k11, btScalar k12, btScalar k22,
                                                   btScalar w1, btScalar w2, btScalar limit) {
    const btScalar size = std::max({std::fabs(w1), std::fabs(w2), limit});
    if (std::isfinite(size) && (size > btScalar(1e6) || (size > 0 && size < btScalar(1e-6)))) {
        const int e = std::ilogb(size);
        const auto [l1, l2] = detail::friction_disk_unscaled(
            k11, k12, k22, std::scalbn(w1, -e), std::scalbn(w2, -e), std::scalbn(limit, -e));
        return {std::scalbn(l1, e), std::scalbn(l2, e)};
    }
    return detail::friction_disk_unscaled(k11, k12, k22, w1, w2, limit);
}

class CoulombSolver : public btSequentialImpulseConstraintSolver {
  public:
    /// The friction model (above); the engine's is FrictionModel::disk.
    void set_friction_model(FrictionModel m) { model_ = m; }
    /// The iteration (above); the engine's default is SolverMethod::pgs.
    void set_method(SolverMethod m) { method_ = m; }
    /// Newton steps after block_nncg's iterations (SimulationOptions::newton_steps; 0: none)
    void set_newton_steps(int steps) { newton_steps_ = steps; }
    /// A test hook (tests/engine/bullet/coulomb_solver_test.cpp), not part of any API: forces
    /// the block methods' path (BlockPath above) where the structure allows it. band_generic
    /// takes the generic loops on a chain that would take the fast ones (elsewhere the
    /// profile, as automatic); profile takes the profile on any structure; automatic (the
    /// default, what the engine always uses) and band_fast choose as BlockPath says.
    void force_block_path(BlockPath p) { forced_path_ = p; }
    /// The path the last factor took (band_fast, band_generic or profile: one factor per
    /// group Bullet hands over, each step); automatic before any step of a block method.
    BlockPath block_path() const { return block_path_; }

    // Solves the contacts and joints of a group in an order of their own (by the bodies'
    // user indices, then the contact's parts; joints by their user constraint id), not in the
    // order Bullet hands them over. Bullet's order comes from an unstable sort by simulation
    // island of every manifold the dispatcher holds, empty ones included, and islands are
    // merged by every pair of the broadphase, including pairs whose bounding boxes no longer
    // overlap but which its incremental clean-up has not reached yet. So it depends on the
    // broadphase's history, which a world rebuilt by PhysicsWorld::copy_state_from does not
    // share with one that was never rebuilt: a clone and its original would agree with each
    // other but not with a twin that was never cloned. Each contact's and joint's rows depend
    // only on its bodies, so with pgs solving groups together or apart gives the same bits once
    // the order within each group is fixed. nncg's and block_nncg's conjugate-gradient step
    // takes each set of bodies joined by joints or contacts on its own (split_sets), and so do
    // the Newton steps, so with them too a 14-module chain with a second one 3 m away moves to
    // the bit as alone (it did not when nncg's beta was one for the whole group). block_nncg
    // takes K's entries in double for each robot on its own (factor_band's chains,
    // factor_block's parts), not for the whole group where one robot needs it. Bullet batches
    // islands into a group until it holds more than 128 joints and manifolds, in the order of
    // their ids; clones have followed their originals in every world tried (20 rolling chains
    // meeting each other, cloned at five times).
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
    // Bullet's iteration for the joint and normal rows, then the friction disks (Bullet's own
    // order: joints, normals, friction)
    btScalar solveSingleIteration(int iteration, btCollisionObject** bodies, int body_count,
                                  btPersistentManifold** manifolds, int manifold_count,
                                  btTypedConstraint** constraints, int constraint_count,
                                  const btContactSolverInfo& info, btIDebugDraw* draw) override {
        if (method_ != SolverMethod::pgs && model_ == FrictionModel::disk)
            return own_iteration(iteration, constraints, constraint_count, info);
        if (model_ == FrictionModel::per_step) {
            return btSequentialImpulseConstraintSolver::solveSingleIteration(
                iteration, bodies, body_count, manifolds, manifold_count, constraints,
                constraint_count, info, draw);
        }
        // Bullet's iteration sees no friction rows; they stay in the pool (a smaller size
        // keeps their memory) for the write-back of solveGroupCacheFriendlyFinish
        const int rows = m_tmpSolverContactFrictionConstraintPool.size();
        m_tmpSolverContactFrictionConstraintPool.resizeNoInitialize(0);
        btScalar residual = btSequentialImpulseConstraintSolver::solveSingleIteration(
            iteration, bodies, body_count, manifolds, manifold_count, constraints, constraint_count,
            info, draw);
        m_tmpSolverContactFrictionConstraintPool.resizeNoInitialize(rows);
        if (iteration < info.m_numIterations) residual = btMax(residual, solve_friction());
        return residual;
    }

    // the iterations, then (newton_steps_ > 0, block_nncg, newton_step.h) that many Newton steps
    // on the whole step's problem after block_nncg's sweeps; without them exactly Bullet's
    btScalar solveGroupCacheFriendlyIterations(btCollisionObject** bodies, int body_count,
                                               btPersistentManifold** manifolds, int manifold_count,
                                               btTypedConstraint** constraints,
                                               int constraint_count,
                                               const btContactSolverInfo& info,
                                               btIDebugDraw* draw) override {
        const btScalar residual =
            btSequentialImpulseConstraintSolver::solveGroupCacheFriendlyIterations(
                bodies, body_count, manifolds, manifold_count, constraints, constraint_count, info,
                draw);
        if (newton_steps_ > 0 && method_ == SolverMethod::block_nncg &&
            model_ == FrictionModel::disk && old_style_.empty()) {
            newton_.run(m_tmpSolverNonContactConstraintPool, m_tmpSolverContactConstraintPool,
                        m_tmpSolverContactFrictionConstraintPool, m_tmpSolverBodyPool, set_of_body_,
                        sets_, newton_steps_);
        }
        return residual;
    }

    void convertContacts(btPersistentManifold** manifolds, int count,
                         const btContactSolverInfo& info) override {
        for (int i = 0; i < count; ++i)
            convert(*manifolds[i], info);
    }

    btScalar solveGroupCacheFriendlyFinish(btCollisionObject** bodies, int count,
                                           const btContactSolverInfo& info) override {
        // the friction impulse of each contact along its directions, for contacts(): Bullet's
        // own write-back (without SOLVER_USE_2_FRICTION_DIRECTIONS) keeps only the first row's,
        // and writes it after this (then empties the pools): the values are kept aside and
        // written once it has
        written_.clear();
        for (int k = 0; k < m_tmpSolverContactConstraintPool.size(); ++k) {
            const btSolverConstraint& c = m_tmpSolverContactConstraintPool[k];
            Written w;
            w.point = static_cast<btManifoldPoint*>(c.m_originalContactPoint);
            const int first = c.m_frictionIndex;
            const int rows = m_tmpSolverContactFrictionConstraintPool.size();
            const btSolverConstraint& r1 = m_tmpSolverContactFrictionConstraintPool[first];
            const bool two =
                first + 1 < rows &&
                m_tmpSolverContactFrictionConstraintPool[first + 1].m_frictionIndex == k;
            w.lateral1 = r1.m_appliedImpulse;
            w.lateral2 =
                two ? m_tmpSolverContactFrictionConstraintPool[first + 1].m_appliedImpulse : 0;
            w.dir1 = w.point->m_lateralFrictionDir1;
            w.dir2 = w.point->m_lateralFrictionDir2;
            // kept for the next step's warm start along two axes of the normal alone (the
            // rows' own axes follow the slip, and a point Bullet's manifold replaces keeps
            // its impulses but not its axes): the same friction, as contacts() reads it
            if (warm_friction() && two) {
                const btSolverConstraint& r2 = m_tmpSolverContactFrictionConstraintPool[first + 1];
                const btVector3 f = r1.m_contactNormal1 * r1.m_appliedImpulse +
                                    r2.m_contactNormal1 * r2.m_appliedImpulse;
                btPlaneSpace1(w.point->m_normalWorldOnB, w.dir1, w.dir2);
                w.lateral1 = f.dot(w.dir1);
                w.lateral2 = f.dot(w.dir2);
            }
            written_.push_back(w);
        }
        const btScalar residual =
            btSequentialImpulseConstraintSolver::solveGroupCacheFriendlyFinish(bodies, count, info);
        for (const Written& w : written_) {
            w.point->m_appliedImpulseLateral1 = w.lateral1;
            w.point->m_appliedImpulseLateral2 = w.lateral2;
            w.point->m_lateralFrictionDir1 = w.dir1;
            w.point->m_lateralFrictionDir2 = w.dir2;
        }
        return residual;
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

    // the relative velocity along a row now: its velocity at the step's start (in its right
    // hand side) plus the change the impulses applied so far made
    static btScalar row_velocity(const btSolverConstraint& c, btSolverBody& a, btSolverBody& b) {
        return c.m_contactNormal1.dot(a.internalGetDeltaLinearVelocity()) +
               c.m_relpos1CrossNormal.dot(a.internalGetDeltaAngularVelocity()) +
               c.m_contactNormal2.dot(b.internalGetDeltaLinearVelocity()) +
               c.m_relpos2CrossNormal.dot(b.internalGetDeltaAngularVelocity()) -
               c.m_rhs / c.m_jacDiagABInv;
    }
    static void apply(btSolverConstraint& c, btSolverBody& a, btSolverBody& b, btScalar impulse) {
        a.internalApplyImpulse(c.m_contactNormal1 * a.internalGetInvMass(), c.m_angularComponentA,
                               impulse);
        b.internalApplyImpulse(c.m_contactNormal2 * b.internalGetInvMass(), c.m_angularComponentB,
                               impulse);
        c.m_appliedImpulse += impulse;
    }

    // One pass over the friction disks: each contact's two rows get the impulse friction_disk
    // (above) gives them, given every other row's. Returns the largest squared velocity
    // change, as Bullet's rows do.
    btScalar solve_friction(bool backward = false) {
        btScalar worst = 0;
        const int n = m_tmpSolverContactFrictionConstraintPool.size();
        for (int i = 0; i + 1 < n; i += 2) {
            const int k = backward ? (n & ~1) - 2 - i : i;
            btSolverConstraint& r1 = m_tmpSolverContactFrictionConstraintPool[k];
            btSolverConstraint& r2 = m_tmpSolverContactFrictionConstraintPool[k + 1];
            const btScalar normal =
                m_tmpSolverContactConstraintPool[r1.m_frictionIndex].m_appliedImpulse;
            const btScalar limit = r1.m_friction * btMax(normal, btScalar(0));
            btSolverBody& a = m_tmpSolverBodyPool[r1.m_solverBodyIdA];
            btSolverBody& b = m_tmpSolverBodyPool[r1.m_solverBodyIdB];
            const btScalar k11 = 1 / r1.m_jacDiagABInv, k22 = 1 / r2.m_jacDiagABInv;
            const btScalar k12 = r1.m_relpos1CrossNormal.dot(r2.m_angularComponentA) +
                                 r1.m_relpos2CrossNormal.dot(r2.m_angularComponentB);
            const btScalar old1 = r1.m_appliedImpulse, old2 = r2.m_appliedImpulse;
            const btScalar v1 = row_velocity(r1, a, b), v2 = row_velocity(r2, a, b);
            const btScalar w1 = v1 - k11 * old1 - k12 * old2;
            const btScalar w2 = v2 - k12 * old1 - k22 * old2;
            const auto [l1, l2] = friction_disk(k11, k12, k22, w1, w2, limit);
            apply(r1, a, b, l1 - old1);
            apply(r2, a, b, l2 - old2);
            worst = btMax(worst, btMax((l1 - old1) * (l1 - old1) * k11 * k11,
                                       (l2 - old2) * (l2 - old2) * k22 * k22));
        }
        return worst;
    }

    // One sweep as Bullet's iteration does it (joint rows, the joints' old-style solve, normal
    // rows, then the friction disks), forwards or backwards (the reverse order throughout)
    btScalar sweep(int iteration, btTypedConstraint** constraints, int constraint_count,
                   const btContactSolverInfo& info, bool backward) {
        btScalar residual = 0;
        if (iteration == 0) {
            // every motor starts the step in the block (solve_block takes out the ones that
            // reach their torque limit)
            at_limit_.assign(m_tmpSolverNonContactConstraintPool.size(), 0);
            if (uses_block()) factor_block();
            list_swept();
            // the constraints whose old-style solve does something: btHingeConstraint's is
            // btTypedConstraint's, which does nothing (only btConeTwistConstraint has one)
            old_style_.clear();
            for (int j = 0; j < constraint_count; ++j) {
                if (constraints[j]->isEnabled() &&
                    constraints[j]->getConstraintType() != HINGE_CONSTRAINT_TYPE) {
                    old_style_.push_back(j);
                }
            }
        }
        if (uses_block()) residual = solve_block();
        const int joints = static_cast<int>(swept_.size());
        auto joint_row = [&](int k) {
            btSolverConstraint& c = m_tmpSolverNonContactConstraintPool[swept_[k]];
            if (iteration >= c.m_overrideNumSolverIterations) return;
            const btScalar r = m_resolveSingleConstraintRowGeneric(
                m_tmpSolverBodyPool[c.m_solverBodyIdA], m_tmpSolverBodyPool[c.m_solverBodyIdB], c);
            residual = btMax(residual, r * r);
        };
        auto old_style = [&] {
            for (int j : old_style_) {
                const int a = getOrInitSolverBody(constraints[j]->getRigidBodyA(), info.m_timeStep);
                const int b = getOrInitSolverBody(constraints[j]->getRigidBodyB(), info.m_timeStep);
                constraints[j]->solveConstraintObsolete(m_tmpSolverBodyPool[a],
                                                        m_tmpSolverBodyPool[b], info.m_timeStep);
            }
        };
        const int normals = m_tmpSolverContactConstraintPool.size();
        auto normal_row = [&](int j) {
            const btSolverConstraint& c = m_tmpSolverContactConstraintPool[j];
            const btScalar r = m_resolveSingleConstraintRowLowerLimit(
                m_tmpSolverBodyPool[c.m_solverBodyIdA], m_tmpSolverBodyPool[c.m_solverBodyIdB], c);
            residual = btMax(residual, r * r);
        };
        const bool contacts = iteration < info.m_numIterations;
        if (!backward) {
            for (int j = 0; j < joints; ++j)
                joint_row(j);
            if (contacts) {
                old_style();
                for (int j = 0; j < normals; ++j)
                    normal_row(j);
                residual = btMax(residual, solve_friction());
            }
        } else {
            if (contacts) {
                residual = btMax(residual, solve_friction(true));
                for (int j = normals - 1; j >= 0; --j)
                    normal_row(j);
                old_style();
            }
            for (int j = joints - 1; j >= 0; --j)
                joint_row(j);
        }
        return residual;
    }

    // every row's impulse, joints then normals then friction (for nncg)
    template <class F>
    void for_each_row(F f) {
        for (int j = 0; j < m_tmpSolverNonContactConstraintPool.size(); ++j)
            f(m_tmpSolverNonContactConstraintPool[j]);
        for (int j = 0; j < m_tmpSolverContactConstraintPool.size(); ++j)
            f(m_tmpSolverContactConstraintPool[j]);
        for (int j = 0; j < m_tmpSolverContactFrictionConstraintPool.size(); ++j)
            f(m_tmpSolverContactFrictionConstraintPool[j]);
    }

    // the same rows as pools: f(rows, count, the first's place in that order)
    template <class F>
    void for_each_pool(F f) {
        size_t at = 0;
        for (btConstraintArray* pool :
             {&m_tmpSolverNonContactConstraintPool, &m_tmpSolverContactConstraintPool,
              &m_tmpSolverContactFrictionConstraintPool}) {
            const int n = pool->size();
            if (n > 0) f(&(*pool)[0], n, at);
            at += static_cast<size_t>(n);
        }
    }

    btScalar own_iteration(int iteration, btTypedConstraint** constraints, int constraint_count,
                           const btContactSolverInfo& info) {
        if (method_ == SolverMethod::block)
            return sweep(iteration, constraints, constraint_count, info, false);
        if (method_ == SolverMethod::symmetric)
            return sweep(iteration, constraints, constraint_count, info, iteration % 2 == 1);
        // nncg, block_nncg
        if (iteration == 0) {
            before_.clear();
            for_each_row([&](btSolverConstraint& c) { before_.push_back(c.m_appliedImpulse); });
            direction_.assign(before_.size(), 0);
            previous_ = 0;
            const int bodies = m_tmpSolverBodyPool.size();
            body_before_.resize(2 * static_cast<size_t>(bodies));
            body_direction_.assign(2 * static_cast<size_t>(bodies), btVector3(0, 0, 0));
            for (int b = 0; b < bodies; ++b) {
                body_before_[2 * b] = m_tmpSolverBodyPool[b].internalGetDeltaLinearVelocity();
                body_before_[2 * b + 1] = m_tmpSolverBodyPool[b].internalGetDeltaAngularVelocity();
            }
            split_sets();
        }
        const btScalar residual = sweep(iteration, constraints, constraint_count, info, false);
        if (sets_ > 1) {
            conjugate_sets(iteration, info);
            return residual;
        }
        btScalar* before = before_.data();
        btScalar* direction = direction_.data();
        btScalar d2 = 0;
        for_each_pool([&](btSolverConstraint* rows, int n, size_t at) {
#pragma GCC unroll 4
            for (int j = 0; j < n; ++j) {
                const btScalar d = rows[j].m_appliedImpulse - before[at + j];
                d2 += d * d;
            }
        });
        const int last = btMax(m_maxOverrideNumSolverIterations, info.m_numIterations) - 1;
        const btScalar beta = iteration == 0 || !(previous_ > 0) ? 0 : d2 / previous_;
        const bool step = beta > 0 && beta <= 1 && iteration < last;
        // the rows' impulses move by beta p; the bodies' velocities by what those impulses do,
        // M^-1 J' beta p, kept per body (beta times last step's, plus this sweep's change)
        for_each_pool([&](btSolverConstraint* rows, int n, size_t at) {
            conjugate_rows(rows, before + at, direction + at, n, step, beta);
        });
        const int bodies = m_tmpSolverBodyPool.size();
        for (int b = 0; b < bodies; ++b)
            conjugate_body(b, step, beta);
        previous_ = d2;
        return residual;
    }

    // nncg's sets of bodies (joined by joints or touching; sets_ of them, set_of_body_, -1 for
    // a fixed body, and the rows as runs of one set, runs_): each takes its own
    // conjugate-gradient step, so a robot's solve does not depend on what else Bullet hands
    // over with it (a second robot 3 m away changed a 14-module chain's bits when beta was one
    // for the whole group)
    void split_sets() {
        const int bodies = m_tmpSolverBodyPool.size();
        set_parent_.resize(static_cast<size_t>(bodies));
        for (int b = 0; b < bodies; ++b)
            set_parent_[b] = b;
        const auto root = [&](int x) {
            while (set_parent_[x] != x) {
                set_parent_[x] = set_parent_[set_parent_[x]];
                x = set_parent_[x];
            }
            return x;
        };
        const auto valid = [&](int b) { return b >= 0 && b < bodies && moving(b); };
        // joints and normals: a friction row joins what its normal does
        for (btConstraintArray* pool :
             {&m_tmpSolverNonContactConstraintPool, &m_tmpSolverContactConstraintPool}) {
            for (int j = 0; j < pool->size(); ++j) {
                const btSolverConstraint& c = (*pool)[j];
                const int a = c.m_solverBodyIdA, b = c.m_solverBodyIdB;
                if (!valid(a) || !valid(b)) continue;
                const int ra = root(a), rb = root(b);
                if (ra != rb) set_parent_[std::max(ra, rb)] = std::min(ra, rb);
            }
        }
        set_of_body_.assign(static_cast<size_t>(bodies), -1);
        sets_ = 0;
        set_number_.assign(static_cast<size_t>(bodies), -1);
        for (int b = 0; b < bodies; ++b) {
            if (!valid(b)) continue;
            int& k = set_number_[root(b)];
            if (k < 0) k = sets_++;
            set_of_body_[b] = k;
        }
        runs_.clear();
        if (sets_ < 2) return;  // one set: own_iteration's own path
        // the rows as runs of one set within one pool (a robot's rows lie together: the
        // solver orders them by their bodies)
        int pool = 0;
        for_each_pool([&](btSolverConstraint* rows, int count, size_t at) {
            for (int j = 0; j < count; ++j) {
                const int a = rows[j].m_solverBodyIdA, b = rows[j].m_solverBodyIdB;
                const int k = valid(a) ? set_of_body_[a] : (valid(b) ? set_of_body_[b] : -1);
                if (runs_.empty() || runs_.back().pool != pool || runs_.back().set != k) {
                    runs_.push_back(Run{pool, at + j, at + j, k});
                }
                runs_.back().end = at + j + 1;
            }
            ++pool;
        });
        previous_sets_.assign(static_cast<size_t>(sets_), 0);
    }

    // nncg's step after a sweep with each set's own beta (own_iteration with more than one set)
    void conjugate_sets(int iteration, const btContactSolverInfo& info) {
        const size_t n = static_cast<size_t>(sets_);
        d2_sets_.assign(n, 0);
        beta_sets_.assign(n, 0);
        step_sets_.assign(n, 0);
        btScalar* before = before_.data();
        btScalar* direction = direction_.data();
        // each run with its pool's rows and their first's place: rows[j - at] is row j
        const auto each_run = [&](auto f) {
            size_t r = 0;
            int pool = 0;
            for_each_pool([&](btSolverConstraint* rows, int, size_t at) {
                for (; r < runs_.size() && runs_[r].pool == pool; ++r)
                    f(runs_[r], rows, at);
                ++pool;
            });
        };
        each_run([&](const Run& run, btSolverConstraint* rows, size_t at) {
            if (run.set < 0) return;
            btScalar& d2 = d2_sets_[static_cast<size_t>(run.set)];
            for (size_t j = run.begin; j < run.end; ++j) {
                const btScalar d = rows[j - at].m_appliedImpulse - before[j];
                d2 += d * d;
            }
        });
        const int last = btMax(m_maxOverrideNumSolverIterations, info.m_numIterations) - 1;
        for (size_t k = 0; k < n; ++k) {
            const btScalar previous = previous_sets_[k];
            beta_sets_[k] = iteration == 0 || !(previous > 0) ? 0 : d2_sets_[k] / previous;
            step_sets_[k] = beta_sets_[k] > 0 && beta_sets_[k] <= 1 && iteration < last;
            previous_sets_[k] = d2_sets_[k];
        }
        const auto stepping = [&](int set) {
            return set >= 0 && step_sets_[static_cast<size_t>(set)] != 0;
        };
        const auto beta_of = [&](int set) {
            return set >= 0 ? beta_sets_[static_cast<size_t>(set)] : btScalar(0);
        };
        each_run([&](const Run& run, btSolverConstraint* rows, size_t at) {
            conjugate_rows(rows + (run.begin - at), before + run.begin, direction + run.begin,
                           static_cast<int>(run.end - run.begin), stepping(run.set),
                           beta_of(run.set));
        });
        const int bodies = m_tmpSolverBodyPool.size();
        for (int b = 0; b < bodies; ++b)
            conjugate_body(b, stepping(set_of_body_[b]), beta_of(set_of_body_[b]));
    }

    // nncg's step on n rows (their impulses before the sweep b, the direction p): with `step`,
    // the impulses move by beta p and p becomes beta p + this sweep's change; else p is that
    // change
    static void conjugate_rows(btSolverConstraint* rows, btScalar* b, btScalar* p, int n, bool step,
                               btScalar beta) {
        if (step) {
#pragma GCC unroll 4
            for (int j = 0; j < n; ++j) {
                btScalar& impulse = rows[j].m_appliedImpulse;
                const btScalar d = impulse - b[j];
                const btScalar extra = beta * p[j];
                impulse += extra;
                p[j] = extra + d;
                b[j] = impulse;
            }
        } else {
#pragma GCC unroll 4
            for (int j = 0; j < n; ++j) {
                const btScalar impulse = rows[j].m_appliedImpulse;
                p[j] = impulse - b[j];
                b[j] = impulse;
            }
        }
    }

    // the same for solver body b's delta velocities: they move by what the rows' step does
    void conjugate_body(int b, bool step, btScalar beta) {
        btSolverBody& s = m_tmpSolverBodyPool[b];
        btVector3* v[2] = {&s.internalGetDeltaLinearVelocity(),
                           &s.internalGetDeltaAngularVelocity()};
        for (int k = 0; k < 2; ++k) {
            const size_t at = 2 * static_cast<size_t>(b) + k;
            const btVector3 d = *v[k] - body_before_[at];
            if (step) {
                const btVector3 extra = body_direction_[at] * beta;
                *v[k] += extra;
                body_direction_[at] = extra + d;
            } else {
                body_direction_[at] = d;
            }
            body_before_[at] = *v[k];
        }
    }

    // the joint rows each sweep solves one by one: those not in the block (all of them for the
    // methods without one)
    void list_swept() {
        swept_.clear();
        for (int j = 0; j < m_tmpSolverNonContactConstraintPool.size(); ++j) {
            if (!uses_block() || !in_block_[j]) swept_.push_back(j);
        }
    }

    // whether a joint row is a motor's: bounded by +-its largest impulse (a hinge's limit row is
    // bounded on one side only, and one that is both motor and limit, at its limit, is too)
    static bool is_motor(const btSolverConstraint& c) {
        return c.m_upperLimit > 0 && c.m_upperLimit < SIMD_INFINITY / 2 &&
               c.m_lowerLimit == -c.m_upperLimit;
    }

    // block: the block rows' system K dl = r, K = J M^-1 J' (+ the rows' cfm), r the change each
    // row's own update would make, over its diagonal: the joints' rows without bounds and the
    // motors' rows, a motor's as if it had none. Where that takes a motor past its torque limit
    // the motor is held at the limit and leaves the block for the rest of the step (swept one
    // by one, as pgs does, with its bounds), K is factored again without it and the system
    // solved again: the motors in the block are then exactly at their commanded speed, the
    // others at their limit. Factored at the first iteration.
    btScalar solve_block() {
        for (;;) {
            solve_block_system();
            if (!motors_past_limit()) return apply_block();
            factor_block();
            list_swept();
        }
    }

    // the block's rows, f(row in the joint pool, its place in rhs_): in the band's slots
    // (band_ not empty) or in block_'s order
    template <class F>
    void for_each_block_row(F f) {
        if (!band_.empty()) {
            const int count = static_cast<int>(band_.size());
            for (int b = 0; b < count; ++b) {
                for (int r = 0; r < kBandRows; ++r) {
                    const int row = band_rows_[b].row[r];
                    if (row >= 0) f(row, rhs_[b * kBandRows + r]);
                }
            }
            return;
        }
        const int n = static_cast<int>(block_.size());
        for (int i = 0; i < n; ++i)
            f(block_[i], rhs_[i]);
    }

    // the block's solution into rhs_
    void solve_block_system() {
        btConstraintArray& pool = m_tmpSolverNonContactConstraintPool;
        if (band_fast_) {
            const int count = static_cast<int>(band_.size());
            for (int b = 0; b < count; ++b)
                band_rhs(band_rows_[b], &pool[0], &m_tmpSolverBodyPool[0], &rhs_[b * kBandRows]);
            band_solve(band_.data(), count, rhs_.data());
            return;
        }
        std::fill(rhs_.begin(), rhs_.end(), 0.0);
        for_each_block_row([&](int row, double& r) {
            const btSolverConstraint& c = pool[row];
            btSolverBody& a = m_tmpSolverBodyPool[c.m_solverBodyIdA];
            btSolverBody& b = m_tmpSolverBodyPool[c.m_solverBodyIdB];
            r = (c.m_rhs - c.m_appliedImpulse * c.m_cfm) / c.m_jacDiagABInv -
                (row_velocity(c, a, b) + c.m_rhs / c.m_jacDiagABInv);
        });
        if (!band_.empty()) {
            band_solve(band_.data(), static_cast<int>(band_.size()), rhs_.data());
        } else {
            profile_solve();
        }
    }

    // the motors the solution in rhs_ takes past their limit: each held at its limit (applied)
    // and marked to leave the block; returns whether there was one
    bool motors_past_limit() {
        bool any = false;
        for_each_block_row([&](int row, double& r) {
            btSolverConstraint& c = m_tmpSolverNonContactConstraintPool[row];
            if (c.m_upperLimit >= SIMD_INFINITY / 2) return;
            const btScalar impulse = c.m_appliedImpulse + static_cast<btScalar>(r);
            if (impulse <= c.m_upperLimit && impulse >= c.m_lowerLimit) return;
            const btScalar limit = impulse > c.m_upperLimit ? c.m_upperLimit : c.m_lowerLimit;
            apply(c, m_tmpSolverBodyPool[c.m_solverBodyIdA], m_tmpSolverBodyPool[c.m_solverBodyIdB],
                  limit - c.m_appliedImpulse);
            at_limit_[static_cast<size_t>(row)] = 1;
            any = true;
        });
        return any;
    }

    // the solution in rhs_ applied to the rows and bodies; the largest squared velocity change
    btScalar apply_block() {
        btConstraintArray& pool = m_tmpSolverNonContactConstraintPool;
        btScalar residual = 0;
        if (band_fast_) {
            const int count = static_cast<int>(band_.size());
            for (int b = 0; b < count; ++b) {
                residual = band_apply(band_rows_[b], &pool[0], &m_tmpSolverBodyPool[0],
                                      &rhs_[b * kBandRows], residual);
            }
            return residual;
        }
        for_each_block_row([&](int row, double& r) {
            btSolverConstraint& c = pool[row];
            const btScalar d = static_cast<btScalar>(r);
            apply(c, m_tmpSolverBodyPool[c.m_solverBodyIdA], m_tmpSolverBodyPool[c.m_solverBodyIdB],
                  d);
            residual = btMax(residual, d * d / (c.m_jacDiagABInv * c.m_jacDiagABInv));
        });
        return residual;
    }

    // L y = r, D z = y, L' x = z (in place) on the profile
    void profile_solve() {
        profile_substitute(chol_.data(), profile_start_.data(), diag_.data(), first_.data(),
                           static_cast<int>(block_.size()), rhs_.data());
    }

    // a body the solver moves (a fixed body has no inverse mass)
    bool moving(int body) const {
        return !m_tmpSolverBodyPool[body].m_invMass.fuzzyZero();
    }

    // a rigid body that takes impulses with factors of 1, as the block's fast and precise
    // paths assume (not Bullet's shared fixed body, not a body locked along an axis)
    bool plain(int body) const {
        const btSolverBody& s = m_tmpSolverBodyPool[body];
        return s.m_originalBody && s.m_linearFactor == btVector3(1, 1, 1) &&
               s.m_angularFactor == btVector3(1, 1, 1);
    }

    // J_i M^-1 J_j' over the bodies rows i and j share
    btScalar coupling(const btSolverConstraint& x, const btSolverConstraint& y) const {
        btScalar sum = 0;
        auto side = [&](int body, const btVector3& lin, const btVector3& ang) {
            const btSolverBody& s = m_tmpSolverBodyPool[body];
            if (y.m_solverBodyIdA == body)
                sum += lin.dot(y.m_contactNormal1 * s.internalGetInvMass()) +
                       ang.dot(y.m_angularComponentA);
            if (y.m_solverBodyIdB == body)
                sum += lin.dot(y.m_contactNormal2 * s.internalGetInvMass()) +
                       ang.dot(y.m_angularComponentB);
        };
        side(x.m_solverBodyIdA, x.m_contactNormal1, x.m_relpos1CrossNormal);
        if (x.m_solverBodyIdB != x.m_solverBodyIdA)
            side(x.m_solverBodyIdB, x.m_contactNormal2, x.m_relpos2CrossNormal);
        return sum;
    }

    void factor_block() {
        btConstraintArray& pool = m_tmpSolverNonContactConstraintPool;
        const btScalar big = SIMD_INFINITY / 2;
        block_.clear();
        in_block_.assign(pool.size(), 0);
        for (int j = 0; j < pool.size(); ++j) {
            const btSolverConstraint& c = pool[j];
            const bool equality = c.m_lowerLimit <= -big && c.m_upperLimit >= big;
            if ((equality || (is_motor(c) && !at_limit_[static_cast<size_t>(j)])) &&
                c.m_jacDiagABInv > 0) {
                block_.push_back(j);
                in_block_[j] = 1;
            }
        }
        const int n = static_cast<int>(block_.size());
        if (forced_path_ != BlockPath::profile && factor_band()) {
            rhs_.assign(band_.size() * kBandRows, 0);
            if (forced_path_ == BlockPath::band_generic) band_fast_ = false;
            block_path_ = band_fast_ ? BlockPath::band_fast : BlockPath::band_generic;
            return;
        }
        // the profile: solve_block takes it where band_ is empty
        rhs_.assign(n, 0);
        band_.clear();
        band_fast_ = false;
        block_path_ = BlockPath::profile;
        // the rows coupled to row i are those earlier on its bodies (a fixed body couples none):
        // its profile starts at the first of them
        rows_of_body_.resize(m_tmpSolverBodyPool.size());
        for (std::vector<int>& rows : rows_of_body_)
            rows.clear();
        first_.assign(n, 0);
        diag_.assign(n, 0);
        profile_start_.assign(static_cast<size_t>(n) + 1, 0);
        // the block's parts (rows joined through shared moving bodies: a robot), each row's
        // part by its first row, and whether every moving body of a part has factors 1 (its
        // rows can be taken precisely)
        part_.resize(static_cast<size_t>(n));
        part_ordinary_.assign(static_cast<size_t>(n), 1);
        for (int i = 0; i < n; ++i) {
            const btSolverConstraint& x = pool[block_[i]];
            const int bodies[2] = {x.m_solverBodyIdA, x.m_solverBodyIdB};
            int first = i;
            part_[i] = i;
            for (int body : bodies) {
                if (!moving(body) || rows_of_body_[body].empty()) continue;
                first = std::min(first, rows_of_body_[body].front());
                join_parts(i, rows_of_body_[body].front());
            }
            first_[i] = first;
            profile_start_[i + 1] = profile_start_[i] + static_cast<size_t>(i - first + 1);
            for (int body : bodies) {
                if (moving(body) && (body == bodies[0] || bodies[0] != bodies[1]))
                    rows_of_body_[body].push_back(i);
            }
        }
        chol_.resize(profile_start_[n]);
        // each part on its own, as band_matrix takes each chain: K's entries in float unless the
        // part is large or they fail. A part's rows couple to no other part's, so its entries,
        // pivots and factor do not depend on the other parts (their columns in its profile hold
        // zeros), whichever way they are taken.
        part_rows_.assign(static_cast<size_t>(n), 0);
        for (int i = 0; i < n; ++i) {
            const int p = find_part(i);
            part_[i] = p;
            ++part_rows_[p];
            const btSolverConstraint& x = pool[block_[i]];
            for (int body : {x.m_solverBodyIdA, x.m_solverBodyIdB}) {
                if (moving(body) && !plain(body)) part_ordinary_[p] = 0;
            }
        }
        const int large = kPreciseBand * (kBandRows - 1);
        precise_.assign(static_cast<size_t>(n), 0);
        for (int i = 0; i < n; ++i) {
            const int p = part_[i];
            precise_[i] = part_ordinary_[p] && part_rows_[p] >= large;
        }
        profile_matrix();
        const auto own = [&](int i) { return 1 / pool[block_[i]].m_jacDiagABInv; };
        // L D L' on the profile: L(i,j) is zero left of first_[i], and so is its fill; a
        // redundant row keeps its own diagonal, as pgs would solve it
        ratio_.resize(static_cast<size_t>(n));
        profile_factor(chol_.data(), profile_start_.data(), diag_.data(), first_.data(), n, own,
                       ratio_.data());
        // a part whose float factor failed: each of its rows precise, and the whole factored
        // again (the other parts' bits unchanged)
        std::vector<char>& failed = part_failed_;
        failed.assign(static_cast<size_t>(n), 0);
        for (int i = 0; i < n; ++i) {
            const int p = part_[i];
            if (!(ratio_[i] >= kFloatPivot) && part_ordinary_[p] && !precise_[i]) failed[p] = 1;
        }
        bool again = false;
        for (int i = 0; i < n; ++i) {
            if (!failed[part_[i]]) continue;
            precise_[i] = 1;
            again = true;
        }
        if (again) {
            profile_matrix();
            profile_factor(chol_.data(), profile_start_.data(), diag_.data(), first_.data(), n,
                           own);
        }
    }

    // the block's parts (factor_block): union by the smaller first row, so a part's root is its
    // first row
    int find_part(int i) {
        while (part_[i] != i) {
            part_[i] = part_[part_[i]];
            i = part_[i];
        }
        return i;
    }
    void join_parts(int i, int j) {
        i = find_part(i);
        j = find_part(j);
        if (i < j) std::swap(i, j);
        part_[i] = j;
    }

    // K on the profile (first_, profile_start_ and rows_of_body_ made), as band_matrix takes
    // the band's: the rows marked in precise_ (whole parts), each entry J W J' in double
    void profile_matrix() {
        const btConstraintArray& pool = m_tmpSolverNonContactConstraintPool;
        const int n = static_cast<int>(block_.size());
        profile_precise_.resize(static_cast<size_t>(n));
        for (int i = 0; i < n; ++i) {
            const btSolverConstraint& x = pool[block_[i]];
            if (precise_[i]) {
                precise_row(profile_precise_[i], &x, m_tmpSolverBodyPool[x.m_solverBodyIdA],
                            m_tmpSolverBodyPool[x.m_solverBodyIdB]);
            }
        }
        for (int i = 0; i < n; ++i) {
            const bool precise = precise_[i];
            const btSolverConstraint& x = pool[block_[i]];
            const int bodies[2] = {x.m_solverBodyIdA, x.m_solverBodyIdB};
            double* row = &chol_[profile_start_[i]];  // row[j - first_[i]]: column j
            std::fill(row, row + (i - first_[i]), 0.0);
            for (int body : bodies) {
                if (!moving(body)) continue;
                for (int j : rows_of_body_[body]) {
                    if (j >= i) break;
                    const btSolverConstraint& y = pool[block_[j]];
                    row[j - first_[i]] =
                        precise ? precise_coupling(profile_precise_[i], x.m_solverBodyIdA,
                                                   x.m_solverBodyIdB, profile_precise_[j],
                                                   y.m_solverBodyIdA, y.m_solverBodyIdB)
                                : coupling(x, y);
                }
            }
            row[i - first_[i]] = precise ? precise_coupling(profile_precise_[i], x.m_solverBodyIdA,
                                                            x.m_solverBodyIdB, profile_precise_[i],
                                                            x.m_solverBodyIdA, x.m_solverBodyIdB) +
                                               x.m_cfm / x.m_jacDiagABInv
                                         : 1 / x.m_jacDiagABInv + x.m_cfm / x.m_jacDiagABInv;
        }
    }

    // a chain of hinges (block_band.h): the block's rows in groups on the same two bodies, a
    // hinge's 5 rows without bounds and, where it follows them, its motor's row, each group
    // sharing moving bodies with no group but the one before it. Builds and factors K there and
    // returns true; otherwise leaves band_ empty for the profile.
    bool factor_band() {
        band_.clear();
        band_fast_ = false;
        const btConstraintArray& pool = m_tmpSolverNonContactConstraintPool;
        const int n = static_cast<int>(block_.size());
        constexpr int kEquality = kBandRows - 1;  // a hinge's rows without bounds
        auto bodies_of = [&](int i) {
            const btSolverConstraint& c = pool[block_[i]];
            return std::make_pair(c.m_solverBodyIdA, c.m_solverBodyIdB);
        };
        // where each group starts in block_, and its size (kEquality, or kBandRows with a motor)
        group_start_.clear();
        group_size_.clear();
        for (int i = 0; i < n;) {
            if (i + kEquality > n) return false;
            const auto bodies = bodies_of(i);
            if (bodies.first == bodies.second) return false;
            for (int r = 0; r < kEquality; ++r) {
                if (bodies_of(i + r) != bodies || is_motor(pool[block_[i + r]])) return false;
            }
            const bool motor = i + kEquality < n && bodies_of(i + kEquality) == bodies &&
                               is_motor(pool[block_[i + kEquality]]);
            group_start_.push_back(i);
            group_size_.push_back(motor ? kBandRows : kEquality);
            i += motor ? kBandRows : kEquality;
        }
        const int count = static_cast<int>(group_start_.size());
        if (count == 0) return false;
        first_group_of_body_.assign(m_tmpSolverBodyPool.size(), -1);
        band_.resize(count);
        band_rows_.resize(count);
        band_fast_ = true;
        for (int b = 0; b < count; ++b) {
            const auto pair = bodies_of(group_start_[b]);
            const int bodies[2] = {pair.first, pair.second};
            bool ok = true;
            bool coupled = false;
            for (int body : bodies) {
                if (!moving(body)) continue;
                const int first = first_group_of_body_[body];
                if (first == -1) {
                    first_group_of_body_[body] = b;
                } else if (first == b - 1) {
                    coupled = true;
                } else {
                    ok = false;
                }
            }
            if (!ok) {
                band_.clear();
                band_fast_ = false;
                return false;
            }
            // the rows' data for band_rhs and band_apply (used where every body takes
            // impulses as btSolverBody::internalApplyImpulse does with factors of 1) and for K
            const btSolverConstraint* rows[kBandRows];
            BandRows& data = band_rows_[b];
            for (int r = 0; r < kBandRows; ++r) {
                const bool used = r < group_size_[b];
                data.row[r] = used ? block_[group_start_[b] + r] : -1;
                rows[r] = used ? &pool[data.row[r]] : nullptr;
            }
            data.a = bodies[0];
            data.b = bodies[1];
            for (int body : bodies)
                band_fast_ = band_fast_ && plain(body);
            band_rows(data, rows, m_tmpSolverBodyPool);
            band_[b].coupled = coupled;
        }
        // each chain of the band (a run of groups each coupled to the one before: a robot) on
        // its own: K's entries in float unless the chain is long or they fail (band_matrix), so
        // that a chain's bits do not depend on the other chains solved in the same group
        for (int begin = 0; begin < count;) {
            int end = begin + 1;
            while (end < count && band_[end].coupled)
                ++end;
            bool plain_chain = true;
            for (int b = begin; b < end; ++b)
                plain_chain = plain_chain && plain(band_rows_[b].a) && plain(band_rows_[b].b);
            const bool long_chain = end - begin >= kPreciseBand;
            band_matrix(begin, end, plain_chain && long_chain);
            if (!(band_factor(&band_[begin], end - begin) >= kFloatPivot) && plain_chain &&
                !long_chain) {
                band_matrix(begin, end, true);
                band_factor(&band_[begin], end - begin);
            }
            begin = end;
        }
        return true;
    }

    // K of the band's groups [begin, end) (one chain), for band_factor. Its entries as coupling()
    // takes them (in float, the diagonal Bullet's 1 / jacDiagABInv), or, `precise`, as J W J' in
    // double (block_band.h, BandPrecise): on a chain of about a thousand hinges K's float entries
    // make it indefinite (its smallest eigenvalue falls below their rounding), the factor breaks
    // down and the solve sends the chain to NaN (a 1200-link URDF chain lying still, within
    // 60 ms). Precise where the chain has kPreciseBand hinges or more, or where the float
    // factor broke down or kept too few digits (a pivot below kFloatPivot of its row's: long
    // thin rods, long heavy links under strong servos); every other chain keeps the float
    // entries, and its bits. Only for chains of ordinary bodies (plain(): the arms' inertia is
    // the body's own).
    void band_matrix(int begin, int end, bool precise) {
        const btConstraintArray& pool = m_tmpSolverNonContactConstraintPool;
        if (precise) {
            band_precise_.resize(band_.size());
            for (int b = begin; b < end; ++b) {
                const BandRows& data = band_rows_[b];
                const btSolverConstraint* rows[kBandRows];
                for (int r = 0; r < kBandRows; ++r)
                    rows[r] = data.row[r] >= 0 ? &pool[data.row[r]] : nullptr;
                for (int r = 0; r < kBandRows; ++r) {
                    precise_row(band_precise_[b].row[r], rows[r], m_tmpSolverBodyPool[data.a],
                                m_tmpSolverBodyPool[data.b]);
                }
            }
        }
        for (int b = begin; b < end; ++b) {
            BandGroup& g = band_[b];
            const BandRows& data = band_rows_[b];
            // an empty slot: no couplings, a diagonal of 1 (its solution is 0)
            for (int r = 0; r < kBandRows; ++r) {
                for (int c = 0; c < kBandRows; ++c)
                    g.prev[r][c] = g.lower[r][c] = 0;
                g.diag[r] = g.own[r] = 1;
            }
            auto entry = [&](const btSolverConstraint& x, int r, int group, int c) -> double {
                const BandRows& other = band_rows_[group];
                if (!precise) return band_coupling(x, other, c);
                return precise_coupling(band_precise_[b].row[r], data.a, data.b,
                                        band_precise_[group].row[c], other.a, other.b);
            };
            for (int r = 0; r < kBandRows; ++r) {
                if (data.row[r] < 0) continue;
                const btSolverConstraint& x = pool[data.row[r]];
                if (g.coupled) {
                    for (int c = 0; c < kBandRows; ++c) {
                        if (band_rows_[b - 1].row[c] >= 0) g.prev[r][c] = entry(x, r, b - 1, c);
                    }
                }
                for (int c = 0; c < r; ++c)
                    g.lower[r][c] = entry(x, r, b, c);
                g.diag[r] = precise ? entry(x, r, b, r) + x.m_cfm / x.m_jacDiagABInv
                                    : 1 / x.m_jacDiagABInv + x.m_cfm / x.m_jacDiagABInv;
                g.own[r] = 1 / x.m_jacDiagABInv;
            }
        }
    }

    // whether contacts start their friction from the last step's (warm_start_friction)
    bool warm_friction() const {
        return uses_block() && model_ == FrictionModel::disk;
    }

    bool uses_block() const {
        return method_ == SolverMethod::block || method_ == SolverMethod::block_nncg;
    }

    FrictionModel model_ = FrictionModel::disk;
    SolverMethod method_ = SolverMethod::pgs;
    BlockPath forced_path_ = BlockPath::automatic;  // force_block_path
    BlockPath block_path_ = BlockPath::automatic;   // block_path
    std::vector<btScalar> before_, direction_;      // nncg: impulses after the last sweep, p
    // nncg: each solver body's delta velocities (linear, angular) after the last sweep, M^-1 J' p
    std::vector<btVector3> body_before_, body_direction_;
    btScalar previous_ = 0;  // nncg: |d_k-1|^2
    // nncg's sets (split_sets): their number, each row's and body's set, per set |d_k-1|^2, and
    // this sweep's |d_k|^2, beta and whether it steps
    int sets_ = 0;
    std::vector<int> set_parent_, set_number_, set_of_body_;
    struct Run {  // rows [begin, end) of one set (-1: none) in pool `pool` (for_each_row's order)
        int pool;
        size_t begin, end;
        int set;
    };
    std::vector<Run> runs_;
    std::vector<btScalar> previous_sets_, d2_sets_, beta_sets_;
    std::vector<char> step_sets_;
    // block: its rows (indices in the joint pool), which rows are in it, L (below the
    // diagonal, row-major n x n), D, each row's first column of the profile, the right side
    std::vector<int> block_, first_;
    std::vector<std::vector<int>> rows_of_body_;  // block: the rows so far on each solver body
    std::vector<char> in_block_;
    // block: the motor rows held at their limit this step (out of the block), by joint row
    std::vector<char> at_limit_;
    std::vector<int> group_start_, group_size_;  // block, a chain: each group's place in block_
    std::vector<BandPrecise> band_precise_;      // block, a chain: its rows in double (band_matrix)
    std::vector<int> swept_;                     // the joint rows each sweep solves one by one
    std::vector<int> old_style_;  // the constraints whose solveConstraintObsolete each sweep calls
    std::vector<double> chol_, diag_, rhs_;    // block: L on the profile, D, the right side
    std::vector<size_t> profile_start_;        // block: where each row of chol_ starts
    std::vector<PreciseRow> profile_precise_;  // block: its rows in double (profile_matrix)
    // block, the profile: each row's part (a root's: the part's first row), per part its rows
    // and whether it is ordinary or failed in float, per row whether it is taken in double and
    // its pivot over its own diagonal
    std::vector<int> part_, part_rows_;
    std::vector<char> part_ordinary_, part_failed_, precise_;
    std::vector<double> ratio_;
    // block, a chain of hinges: K's factors in blocks (empty: the profile above), and the first
    // group on each solver body
    std::vector<BandGroup> band_;
    std::vector<BandRows> band_rows_;
    bool band_fast_ = false;  // band_rows_ hold the rows (block_band.h)
    std::vector<int> first_group_of_body_;
    std::vector<btPersistentManifold*> sorted_manifolds_;
    // solveGroupCacheFriendlyFinish: each contact point's friction, written after Bullet's own
    struct Written {
        btManifoldPoint* point;
        btScalar lateral1, lateral2;
        btVector3 dir1, dir2;
    };
    std::vector<Written> written_;
    std::vector<btTypedConstraint*> sorted_constraints_;
    int newton_steps_ = 0;
    NewtonStep newton_;  // its work space (newton_step.h)

    void convert(btPersistentManifold& manifold, const btContactSolverInfo& info) {
        // Bullet's solver takes non-const bodies; it changes only their solver data
        auto* a = const_cast<btCollisionObject*>(manifold.getBody0());
        auto* b = const_cast<btCollisionObject*>(manifold.getBody1());
        const int ia = getOrInitSolverBody(*a, info.m_timeStep);
        const int ib = getOrInitSolverBody(*b, info.m_timeStep);
        if (!moving(ia) && !moving(ib)) return;  // two fixed bodies
        const btSolverBody& sa = m_tmpSolverBodyPool[ia];
        const btSolverBody& sb = m_tmpSolverBodyPool[ib];
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
            // the friction impulse the point kept from the last step (warm_friction)
            btVector3 warm(0, 0, 0);
            if (warm_friction()) {
                btVector3 t1, t2;
                btPlaneSpace1(n, t1, t2);
                warm = (t1 * cp.m_appliedImpulseLateral1 + t2 * cp.m_appliedImpulseLateral2) *
                       info.m_warmstartingFactor;
            }
            btScalar relaxation;
            setupContactConstraint(contact, ia, ib, cp, info, relaxation, rel_a, rel_b);
            // a compliant contact's spring acts in the velocity solve at every depth. Bullet
            // hands the positional term of a contact deeper than the split-impulse threshold
            // (4 cm) to the split impulse, which moves the body out without momentum; the
            // spring's soft row is then left with the velocity term alone and lets a heavy body
            // sink through the floor at a steady speed (a 1 m, 850 kg cube on the default floor)
            if ((cp.m_contactPointFlags & BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING) &&
                contact.m_rhsPenetration != 0) {
                contact.m_rhs += contact.m_rhsPenetration;
                contact.m_rhsPenetration = 0;
            }
            contact.m_frictionIndex = m_tmpSolverContactFrictionConstraintPool.size();
            const btScalar speed2 = slip.length2();
            // a sliding contact: its first row along the slip; a resting one: any two directions
            const bool slides = speed2 > kSlideSpeed * kSlideSpeed;
            if (slides) {
                cp.m_lateralFrictionDir1 = slip / btSqrt(speed2);
                cp.m_lateralFrictionDir2 = cp.m_lateralFrictionDir1.cross(n);
            } else {
                btPlaneSpace1(n, cp.m_lateralFrictionDir1, cp.m_lateralFrictionDir2);
            }
            addFrictionConstraint(cp.m_lateralFrictionDir1, ia, ib, index, cp, rel_a, rel_b, a, b,
                                  relaxation, info);
            // the rows: one along the slip (Coulomb: capped at muN), two at rest (static);
            // the disk always two, solved together (solve_friction)
            if (!slides || model_ == FrictionModel::disk) {
                addFrictionConstraint(cp.m_lateralFrictionDir2, ia, ib, index, cp, rel_a, rel_b, a,
                                      b, relaxation, info);
            }
            if (warm_friction()) warm_start_friction(contact, warm);
        }
    }

    // The block methods start a contact's friction disk where the last step left it (times
    // the solver's warm-starting factor, as Bullet does for the normal rows), within the disk
    // of its warm-started normal impulse: chains whose contacts stick need hundreds of
    // iterations to build their friction from zero at a step of 5 ms (docs/performance.md,
    // "Motors in the block, friction warm-started").
    void warm_start_friction(const btSolverConstraint& contact, const btVector3& warm) {
        btSolverConstraint& r1 = m_tmpSolverContactFrictionConstraintPool[contact.m_frictionIndex];
        btSolverConstraint& r2 =
            m_tmpSolverContactFrictionConstraintPool[contact.m_frictionIndex + 1];
        btScalar l1 = warm.dot(r1.m_contactNormal1), l2 = warm.dot(r2.m_contactNormal1);
        const btScalar limit = r1.m_friction * btMax(contact.m_appliedImpulse, btScalar(0));
        const btScalar length2 = l1 * l1 + l2 * l2;
        if (length2 > limit * limit) {
            const btScalar scale = limit > 0 ? limit / btSqrt(length2) : 0;
            l1 *= scale;
            l2 *= scale;
        }
        btSolverBody& a = m_tmpSolverBodyPool[contact.m_solverBodyIdA];
        btSolverBody& b = m_tmpSolverBodyPool[contact.m_solverBodyIdB];
        apply(r1, a, b, l1);
        apply(r2, a, b, l2);
    }
};

}  // namespace gaitlab
