// The Newton step of SimulationOptions::newton_steps (block_nncg only; docs/architecture.md,
// "Physics formulation"): after CoulombSolver's block_nncg iterations, K semi-smooth Newton steps
// on the step's contact problem, solved sparse, each set of bodies joined by joints or contacts on
// its own (run). K = 0: nothing here runs. On the 32-module
// pitch-yaw rolling chain (friction 0.3) 4 steps at 20 iterations move 83.5 mm per cycle against
// 84.6 at 80 iterations (block_nncg alone: 70.6 against 80.8), at 2.0x the default step's CPU
// time where 80 iterations cost 3.0x (docs/performance.md, "A sparse Newton step after the
// sweeps").
//
// The problem, in the rows' impulses lambda: every row's velocity error w = J v - target +
// cfm lambda, v = v0 + M^-1 J' lambda (the solver bodies' delta velocities), and the natural
// residual F(lambda) = lambda - proj(lambda - r w): joint rows and contact normals clamp to their
// bounds (equality rows have infinite ones: F = r w), a contact's two friction rows project
// together onto the disk of radius mu max(lambda_n, 0) (the current normal impulse). r is one
// scalar per row, and per friction PAIR one scalar for both rows: with a different r per row the
// zeros of F are not Coulomb's law (the projection's fixed point puts lambda_t along R w_t, not
// against the slip w_t), so a pair takes factor * 2 / (K_11 + K_22).
//
// A Newton step, with dv the bodies' velocity change and dlambda the rows':
// - active rows (inside their bounds; a friction pair inside its disk: sticking) keep
//   J_i dv + cfm_i dlambda_i = -w_i;
// - rows at a bound (x outside) get dlambda = bound - lambda (a separating normal: -lambda);
// - a sliding pair (x = lambda_t - r w_t outside the disk, a = rho / |x| < 1, xhat = x / |x|,
//   P = a (I - xhat xhat')): dF = (I - P) dlambda_t + r P dw_t - s dlambda_n = -F with
//   s = mu xhat where lambda_n > 0 (0 otherwise, rho's slope), so
//   dlambda_t = c_t - E_t J_t dv + s dlambda_n, c_t = (I - P)^-1 (-F_t),
//   E_t = r P (I - P)^-1 = r a / (1 - a) (I - xhat xhat') (symmetric PSD; friction rows carry no
//   cfm in this solver, solve_friction ignores it too).
// Momentum M dv = J' dlambda with the sliding and inactive rows put in:
//   H dv = g + B_A' dlambda_A, H = M + sum_t J_t' E_t J_t (per body: floor contacts touch one),
//   g the known parts (c_t, s dlambda_n of inactive normals, bound - lambda of inactive rows),
//   B_A = J_A except a pressed normal with a sliding pair: J_n + s' J_t.
// Eliminating dv: S dlambda_A = -w_A - J_A H^-1 g, S = J_A H^-1 B_A' + diag(cfm + reg)
// (+ kNewtonRegulariser S_ii), where reg (sticking friction pairs' kNewtonFrictionDamping) is
// in S alone, not in F (an inexact Newton step, whose fixed point is F's own zero). Where every
// contact is on one moving body (the floor, fixed objects) and the joints join the bodies in
// chains, S is block tridiagonal with the groups "body b's active contact rows + the hinge
// (b, next)'s rows" taken along each chain: block LU, partial pivoting inside each diagonal block
// only, in a fixed order (solve_chain). Otherwise (two robots touching, a robot touching itself
// with self_collision, a box on a robot, a branch or a loop) S is sparse and general, and a
// sliding pair between two moving bodies is not eliminated (its E would couple the two bodies'
// H): its two rows stay unknowns with their own linearised F, A dlambda_t + r P J_t dv - s
// dlambda_n = -F_t, A = I - (1 - r reg) P; Eigen's SparseLU solves it (solve_general,
// newton_step.cpp). On a chain both give the same steps (the 16-module rolling chain forced
// through the general one: the same mm per cycle to 0.1, at 2.1x the CPU time). Then dv, the
// sliding and inactive rows' dlambda, the bodies' change M^-1 J' dlambda, a backtracking line
// search on |F| (the row velocities are linear in the step), and the impulses and the bodies'
// delta velocities written back as CoulombSolver::apply keeps them. Not handled: a body that
// takes impulses with factors other than 1 (locked axes; gaitlab makes none): nothing is done,
// the step is plain block_nncg's.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace gaitlab {

// The constants of the Newton problem (the branch `newton`'s measurements):
// r = kNewtonR / K_ii per row (a friction pair: over its mean diagonal). At r = 1 / K_ii the line
// search took the full step 5-9 % of the time and two steps moved the 32-module chain 69.9 mm per
// cycle (block_nncg alone: 70.6); at 10 / K_ii it takes it about 70 % of the time and the steps
// reach the converged motion.
inline constexpr double kNewtonR = 10;
// Each friction pair's damping of the Newton system, as a fraction of the pair's mean diagonal
// 1 / K_ii, added to S's diagonal (and to a sliding pair's A) but not to F: redundant sticking
// contacts (a module's corners all on the floor) made S singular, and without it 64 % of the
// steps on the 8-module pitch-pitch chain found no decrease of |F|. Until 2026-11-29 it was a
// compliance, in F as well, and that changed the answer: the 16-module pitch-yaw wave on a
// floor of friction 1.0 moved 66.7 mm per cycle at dt 1 ms against 65.0 at 320 iterations
// without Newton steps and 64.5 at the grid's reference (1e-3: 65.2, 1e-4: 64.6). In S alone
// the step's fixed point is F's zero whatever its value: 64.8 (docs/performance.md, "The Newton
// step's friction regularisation").
inline constexpr double kNewtonFrictionDamping = 1e-2;
// S's diagonal is raised by this fraction of itself, contact and joint rows alike: it only keeps
// the block LU's pivots off exact zeros where rows are still redundant (the damping above is
// what makes S regular), six orders below it so that it does not move the steps.
inline constexpr double kNewtonRegulariser = 1e-8;

class NewtonStep {
  public:
    // Runs the steps on the solver's pools, one set of bodies at a time (bodies joined by a
    // joint or touching each other; `set_of_body` numbers each solver body's set from 0 to
    // `sets` - 1, -1 for a fixed body, as CoulombSolver::split_sets finds them): a set's steps,
    // their line search included, depend on its own rows alone, so it gets the same bits
    // whether Bullet hands it over alone or batched with other islands (which islands are
    // batched together depends on the broadphase's history, so a clone's batches need not be
    // its original's: CoulombSolver::solveGroup). False where no set was handled (nothing
    // changed then)
    bool run(btConstraintArray& joints, btConstraintArray& normals, btConstraintArray& friction,
             btAlignedObjectArray<btSolverBody>& pool, const std::vector<int>& set_of_body,
             int sets, int steps) {
        if (friction.size() != 2 * normals.size()) return false;
        if (static_cast<int>(set_of_body.size()) != pool.size()) return false;
        split(joints, normals, set_of_body, sets);
        slot_.assign(static_cast<size_t>(pool.size()), -1);
        bool any = false;
        for (int k = 0; k < nsets_; ++k) {
            if (setup(joints, normals, friction, pool, sets_[k])) {
                solve(pool, steps);
                any = true;
            }
            for (const Body& b : bodies_)
                slot_[b.solver] = -1;
        }
        return any;
    }

  private:
    enum Kind { kClamp, kFriction1, kFriction2 };
    enum State { kActive, kBound, kSliding };
    struct Row {
        btSolverConstraint* c;
        int kind;
        int nb;          // moving bodies (1 or 2)
        int body[2];     // body slots
        double J[2][6];  // per body: linear, angular
        double B[2][6];  // this step's B (J, or a pressed normal's J_n + s' J_t)
        double lo, hi, cfm, c0, r;
        double reg = 0;  // in S (and a sliding pair's A) only: kNewtonFrictionDamping
        int normal;      // friction rows: their normal's row; a normal: its friction's first
        int group;
        // per Newton step
        double lambda, w, dl, dw;
        int state;
        double bound;
        int local;    // place within its group's active rows (-1: not active)
        bool plainB;  // B is J
        // a sliding pair (on its first row): E, c, s
        double e, perp[2], cvec[2], s[2];
        double a;     // a sliding pair: rho / |x|
        double f[2];  // a sliding pair between two moving bodies: its F
    };
    struct Body {
        int solver;
        double inv_mass, mass;
        double inv_inertia[9], inertia[9];
        double V[6];  // delta velocities (linear, angular)
        double Hinv[36];
        double h[6];   // H^-1 g
        double dv[6];  // Newton's dv
        double dV[6];  // M^-1 J' dlambda
        int pos;       // place along all chains (= its group)
        int next;      // the next body along its chain (-1: none)
        int deg;
        int nbr[2];
    };

    // a set of bodies joined by joints or contacts: its contacts' and joints' places in the pools
    struct Set {
        std::vector<int> normals, joints;
    };
    std::vector<Set> sets_;  // the first nsets_ are this step's
    int nsets_ = 0;

    std::vector<Row> rows_;  // the contacts' rows first, then the joints'
    std::vector<Body> bodies_;
    std::vector<int> slot_;                     // solver body -> body slot (-1: not moving)
    std::vector<int> order_;                    // bodies along the chains
    std::vector<std::vector<int>> group_rows_;  // rows of each group (contacts then joints)
    std::vector<std::vector<int>> body_rows_;   // rows on each body
    // per Newton step
    std::vector<std::vector<int>> group_active_;
    std::vector<int> n_;  // active rows per group
    std::vector<size_t> d_off_, l_off_, u_off_, x_off_, v_off_;
    std::vector<double> D_, L_, U_, X_, rhs_, z_;
    std::vector<int> piv_;
    std::vector<size_t> piv_off_;
    std::vector<double> u_;  // per (active row, side): H^-1 B'
    struct On {              // an active row on a body, for S
        const double* J;
        double u[6];
        int row, side, group, local;
        bool plain;
    };
    std::vector<On> on_;
    // the general structure (general_): the system's rows and S as triplets
    bool general_ = false;
    std::vector<int> sys_;
    std::vector<double> diag_;

    // S(i, j) into its block; false where the rows' groups are not neighbours
    bool add_entry(const On& i, const On& j, double v) {
        const int gi = i.group, gj = j.group;
        if (gi == gj) {
            D_[d_off_[gi] + static_cast<size_t>(i.local * n_[gi] + j.local)] += v;
        } else if (gi == gj + 1) {
            L_[l_off_[gi] + static_cast<size_t>(i.local * n_[gj] + j.local)] += v;
        } else if (gj == gi + 1) {
            U_[l_off_[gj] + static_cast<size_t>(i.local * n_[gj] + j.local)] += v;
        } else {
            return false;
        }
        return true;
    }

    static bool plain(const btSolverBody& s) {
        return s.m_originalBody && s.m_linearFactor == btVector3(1, 1, 1) &&
               s.m_angularFactor == btVector3(1, 1, 1);
    }

    static bool inverse3(const double* a, double* out) {
        const double c00 = a[4] * a[8] - a[5] * a[7], c01 = a[5] * a[6] - a[3] * a[8],
                     c02 = a[3] * a[7] - a[4] * a[6];
        const double det = a[0] * c00 + a[1] * c01 + a[2] * c02;
        if (!(std::fabs(det) > 0)) return false;
        const double k = 1 / det;
        out[0] = c00 * k;
        out[1] = (a[2] * a[7] - a[1] * a[8]) * k;
        out[2] = (a[1] * a[5] - a[2] * a[4]) * k;
        out[3] = c01 * k;
        out[4] = (a[0] * a[8] - a[2] * a[6]) * k;
        out[5] = (a[2] * a[3] - a[0] * a[5]) * k;
        out[6] = c02 * k;
        out[7] = (a[1] * a[6] - a[0] * a[7]) * k;
        out[8] = (a[0] * a[4] - a[1] * a[3]) * k;
        return true;
    }

    int slot_of(btAlignedObjectArray<btSolverBody>& pool, int solver) {
        if (pool[solver].m_invMass.fuzzyZero()) return -1;
        if (slot_[solver] >= 0) return slot_[solver];
        const btSolverBody& s = pool[solver];
        if (!plain(s)) return -2;
        Body b{};
        b.solver = solver;
        b.inv_mass = s.m_invMass.x();
        b.mass = 1 / b.inv_mass;
        const btMatrix3x3& m = s.m_originalBody->getInvInertiaTensorWorld();
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                b.inv_inertia[3 * i + j] = m[i][j];
        if (!inverse3(b.inv_inertia, b.inertia)) return -2;
        b.next = -1;
        b.deg = 0;
        b.nbr[0] = b.nbr[1] = -1;
        slot_[solver] = static_cast<int>(bodies_.size());
        bodies_.push_back(b);
        return slot_[solver];
    }

    // each row to its set (sets_, nsets_), in the pools' order
    void split(btConstraintArray& joints, btConstraintArray& normals,
               const std::vector<int>& set_of_body, int sets) {
        nsets_ = sets;
        if (static_cast<int>(sets_.size()) < sets) sets_.resize(static_cast<size_t>(sets));
        for (int k = 0; k < sets; ++k) {
            sets_[k].normals.clear();
            sets_[k].joints.clear();
        }
        const int n = static_cast<int>(set_of_body.size());
        auto set = [&](const btSolverConstraint& c) -> Set* {
            for (const int body : {c.m_solverBodyIdA, c.m_solverBodyIdB}) {
                const int k = body >= 0 && body < n ? set_of_body[body] : -1;
                if (k >= 0 && k < sets) return &sets_[k];
            }
            return nullptr;  // between fixed bodies
        };
        for (int k = 0; k < normals.size(); ++k)
            if (Set* s = set(normals[k])) s->normals.push_back(k);
        for (int k = 0; k < joints.size(); ++k)
            if (Set* s = set(joints[k])) s->joints.push_back(k);
    }

    // a row's data; false where not handled
    bool add_row(btSolverConstraint& c, int kind, btAlignedObjectArray<btSolverBody>& pool) {
        Row r{};
        r.c = &c;
        r.kind = kind;
        r.normal = -1;
        const int sa = slot_of(pool, c.m_solverBodyIdA);
        const int sb =
            c.m_solverBodyIdB == c.m_solverBodyIdA ? -1 : slot_of(pool, c.m_solverBodyIdB);
        if (sa == -2 || sb == -2) return false;
        r.nb = 0;
        auto side = [&](int slot, const btVector3& lin, const btVector3& ang) {
            r.body[r.nb] = slot;
            for (int k = 0; k < 3; ++k) {
                r.J[r.nb][k] = lin[k];
                r.J[r.nb][3 + k] = ang[k];
            }
            ++r.nb;
        };
        if (sa >= 0) side(sa, c.m_contactNormal1, c.m_relpos1CrossNormal);
        if (sb >= 0) side(sb, c.m_contactNormal2, c.m_relpos2CrossNormal);
        if (r.nb == 0) return true;  // on fixed bodies only: nothing to do (not added)
        if (!(c.m_jacDiagABInv > 0)) return kind == kClamp;  // a degenerate joint row: held
        const double jd = c.m_jacDiagABInv;
        r.cfm = kind == kClamp ? c.m_cfm / jd : 0;  // a friction pair's: set by setup
        r.c0 = -c.m_rhs / jd;
        r.lo = c.m_lowerLimit;
        r.hi = c.m_upperLimit;
        r.lambda = c.m_appliedImpulse;
        rows_.push_back(r);
        return true;
    }

    // one set's rows and bodies (slot_ all -1 before); false where not handled
    bool setup(btConstraintArray& joints, btConstraintArray& normals, btConstraintArray& friction,
               btAlignedObjectArray<btSolverBody>& pool, const Set& set) {
        rows_.clear();
        bodies_.clear();
        general_ = false;
        // contacts: normal, then its two friction rows
        for (const int k : set.normals) {
            btSolverConstraint& n = normals[k];
            const int first = n.m_frictionIndex;
            if (first < 0 || first + 1 >= friction.size()) return false;
            btSolverConstraint& f1 = friction[first];
            btSolverConstraint& f2 = friction[first + 1];
            if (f1.m_frictionIndex != k || f2.m_frictionIndex != k) return false;
            const size_t before = rows_.size();
            if (!add_row(n, kClamp, pool)) return false;
            if (rows_.size() == before) continue;  // between fixed bodies
            if (!add_row(f1, kFriction1, pool) || !add_row(f2, kFriction2, pool)) return false;
            if (rows_.size() != before + 3) return false;
            Row& rn = rows_[before];
            Row& r1 = rows_[before + 1];
            Row& r2 = rows_[before + 2];
            for (const Row* f : {&r1, &r2}) {
                if (f->nb != rn.nb) return false;
                for (int side = 0; side < rn.nb; ++side)
                    if (f->body[side] != rn.body[side]) return false;
            }
            if (rn.nb == 2) general_ = true;  // two moving bodies touch
            rn.normal = static_cast<int>(before + 1);
            r1.normal = r2.normal = static_cast<int>(before);
            const double rt = kNewtonR * 2 / (1 / f1.m_jacDiagABInv + 1 / f2.m_jacDiagABInv);
            r1.r = r2.r = rt;
            // the friction pair's damping of the system (its cfm stays 0, as the solver's own
            // rows'): the same for both rows, a fraction of their mean diagonal
            r1.reg = r2.reg =
                kNewtonFrictionDamping * (1 / f1.m_jacDiagABInv + 1 / f2.m_jacDiagABInv) / 2;
            rn.r = kNewtonR * n.m_jacDiagABInv;
            // a rigid contact between two moving bodies (a floor contact is compliant): its normal
            // takes the friction pairs' damping in S too, its four corners on a face as
            // redundant as a sticking pair's rows (newton_test's box sliding on a box, on the
            // default floor, at 5 iterations: 0.2 % off the converged acceleration without it,
            // 0.01 % with it)
            if (rn.nb == 2 && !(rn.cfm > 0)) rn.reg = kNewtonFrictionDamping / n.m_jacDiagABInv;
        }
        for (const int k : set.joints) {
            const size_t before = rows_.size();
            if (!add_row(joints[k], kClamp, pool)) return false;
            if (rows_.size() == before) continue;
            Row& r = rows_.back();
            r.r = kNewtonR * joints[k].m_jacDiagABInv;
            if (r.nb == 2) {
                Body& a = bodies_[r.body[0]];
                Body& b = bodies_[r.body[1]];
                const int ia = r.body[0], ib = r.body[1];
                auto link = [](Body& x, int other) {
                    if (x.nbr[0] == other || x.nbr[1] == other) return true;
                    if (x.deg == 2) return false;
                    x.nbr[x.deg++] = other;
                    return true;
                };
                if (!link(a, ib) || !link(b, ia)) general_ = true;  // branched
            }
        }
        const int nbodies = static_cast<int>(bodies_.size());
        if (nbodies == 0 || rows_.empty()) return false;
        body_rows_.resize(static_cast<size_t>(nbodies));
        for (std::vector<int>& rows : body_rows_)
            rows.clear();
        for (size_t i = 0; i < rows_.size(); ++i) {
            const Row& r = rows_[i];
            for (int k = 0; k < r.nb; ++k)
                body_rows_[r.body[k]].push_back(static_cast<int>(i));
        }
        for (Body& b : bodies_) {
            const btSolverBody& s = pool[b.solver];
            const btVector3& l = s.m_deltaLinearVelocity;
            const btVector3& a = s.m_deltaAngularVelocity;
            for (int k = 0; k < 3; ++k) {
                b.V[k] = l[k];
                b.V[3 + k] = a[k];
            }
        }
        if (!general_) general_ = !chains();
        return true;
    }

    // the chains and their groups (false: the structure is not chains whose rows couple only
    // neighbouring bodies)
    bool chains() {
        // from each end (in slot order), along the links
        const int nbodies = static_cast<int>(bodies_.size());
        order_.clear();
        std::vector<char> seen(static_cast<size_t>(nbodies), 0);
        for (int start = 0; start < nbodies; ++start) {
            if (seen[start] || bodies_[start].deg > 1) continue;
            int prev = -1, at = start;
            while (at >= 0) {
                seen[at] = 1;
                bodies_[at].pos = static_cast<int>(order_.size());
                order_.push_back(at);
                const Body& b = bodies_[at];
                int next = -1;
                for (int k = 0; k < b.deg; ++k)
                    if (b.nbr[k] != prev) next = b.nbr[k];
                bodies_[at].next = next;
                prev = at;
                at = next;
            }
        }
        if (static_cast<int>(order_.size()) != nbodies) return false;  // a loop
        group_rows_.resize(static_cast<size_t>(nbodies));
        for (std::vector<int>& rows : group_rows_)
            rows.clear();
        for (size_t i = 0; i < rows_.size(); ++i) {
            Row& r = rows_[i];
            int g = bodies_[r.body[0]].pos;
            if (r.nb == 2) {
                const int p0 = bodies_[r.body[0]].pos, p1 = bodies_[r.body[1]].pos;
                if (p1 == p0 + 1) {
                    g = p0;
                } else if (p0 == p1 + 1) {
                    g = p1;
                } else {
                    return false;
                }
            }
            r.group = g;
            group_rows_[g].push_back(static_cast<int>(i));
        }
        return true;
    }

    // M^-1 x for a body (6)
    static void minv(const Body& b, const double* x, double* out) {
        for (int k = 0; k < 3; ++k)
            out[k] = b.inv_mass * x[k];
        for (int i = 0; i < 3; ++i)
            out[3 + i] = b.inv_inertia[3 * i] * x[3] + b.inv_inertia[3 * i + 1] * x[4] +
                         b.inv_inertia[3 * i + 2] * x[5];
    }

    static double dot6(const double* a, const double* b) {
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4] + a[5] * b[5];
    }

    double velocity(const Row& r) const {
        double v = r.c0;
        for (int k = 0; k < r.nb; ++k)
            v += dot6(r.J[k], bodies_[r.body[k]].V);
        return v;
    }

    // |F|^2 at lambda + alpha dl, w + alpha dw
    double merit(double alpha) const {
        double sum = 0;
        const size_t n = rows_.size();
        for (size_t i = 0; i < n; ++i) {
            const Row& r = rows_[i];
            const double l = r.lambda + alpha * r.dl, w = r.w + alpha * r.dw;
            if (r.kind == kClamp) {
                const double x = l - r.r * w;
                const double p = x < r.lo ? r.lo : (x > r.hi ? r.hi : x);
                sum += (l - p) * (l - p);
            } else if (r.kind == kFriction1) {
                const Row& r2 = rows_[i + 1];
                const Row& rn = rows_[r.normal];
                const double ln = rn.lambda + alpha * rn.dl;
                const double rho = ln > 0 ? ln * r.c->m_friction : 0;
                const double l2 = r2.lambda + alpha * r2.dl, w2 = r2.w + alpha * r2.dw;
                double x1 = l - r.r * w, x2 = l2 - r.r * w2;
                const double len = std::sqrt(x1 * x1 + x2 * x2);
                if (len > rho) {
                    const double k = len > 0 ? rho / len : 0;
                    x1 *= k;
                    x2 *= k;
                }
                sum += (l - x1) * (l - x1) + (l2 - x2) * (l2 - x2);
            }
        }
        return sum;
    }

    // dense LU with partial pivoting of an n x n row-major block, in place
    static void lu(double* a, int* piv, int n) {
        for (int k = 0; k < n; ++k) {
            int p = k;
            double best = std::fabs(a[k * n + k]);
            for (int i = k + 1; i < n; ++i) {
                const double v = std::fabs(a[i * n + k]);
                if (v > best) {
                    best = v;
                    p = i;
                }
            }
            piv[k] = p;
            if (p != k)
                for (int j = 0; j < n; ++j)
                    std::swap(a[k * n + j], a[p * n + j]);
            const double d = a[k * n + k];
            const double inv = d != 0 ? 1 / d : 0;
            for (int i = k + 1; i < n; ++i) {
                const double f = a[i * n + k] * inv;
                a[i * n + k] = f;
                if (f != 0)
                    for (int j = k + 1; j < n; ++j)
                        a[i * n + j] -= f * a[k * n + j];
            }
        }
    }

    // solves LU x = b in place for m right sides (b row-major n x m)
    static void lu_solve(const double* a, const int* piv, int n, double* b, int m) {
        for (int k = 0; k < n; ++k) {
            if (piv[k] != k)
                for (int j = 0; j < m; ++j)
                    std::swap(b[k * m + j], b[piv[k] * m + j]);
        }
        for (int i = 1; i < n; ++i)
            for (int k = 0; k < i; ++k) {
                const double f = a[i * n + k];
                if (f != 0)
                    for (int j = 0; j < m; ++j)
                        b[i * m + j] -= f * b[k * m + j];
            }
        for (int i = n - 1; i >= 0; --i) {
            for (int k = i + 1; k < n; ++k) {
                const double f = a[i * n + k];
                for (int j = 0; j < m; ++j)
                    b[i * m + j] -= f * b[k * m + j];
            }
            const double d = a[i * n + i];
            const double inv = d != 0 ? 1 / d : 0;
            for (int j = 0; j < m; ++j)
                b[i * m + j] *= inv;
        }
    }

    // 6x6 SPD inverse (Cholesky), out row-major
    static void inverse6(const double* h, double* out) {
        double l[36] = {};
        for (int i = 0; i < 6; ++i)
            for (int j = 0; j <= i; ++j) {
                double s = h[6 * i + j];
                for (int k = 0; k < j; ++k)
                    s -= l[6 * i + k] * l[6 * j + k];
                if (i == j) {
                    l[6 * i + i] = std::sqrt(s > 0 ? s : 1e-300);
                } else {
                    l[6 * i + j] = s / l[6 * j + j];
                }
            }
        // columns of the inverse: L L' x = e_c
        for (int c = 0; c < 6; ++c) {
            double y[6];
            for (int i = 0; i < 6; ++i) {
                double s = i == c ? 1 : 0;
                for (int k = 0; k < i; ++k)
                    s -= l[6 * i + k] * y[k];
                y[i] = s / l[6 * i + i];
            }
            for (int i = 5; i >= 0; --i) {
                double s = y[i];
                for (int k = i + 1; k < 6; ++k)
                    s -= l[6 * k + i] * y[k];
                y[i] = s / l[6 * i + i];
            }
            for (int i = 0; i < 6; ++i)
                out[6 * i + c] = y[i];
        }
    }

    // row i's entry on its body b for S: its J there, u = H_b^-1 B' (B = J unless a pressed
    // normal's with a sliding pair)
    On on_body(int i, int b) const {
        const Row& r = rows_[i];
        const int side = r.body[0] == b ? 0 : 1;
        On o;
        o.J = r.J[side];
        o.plain = r.plainB;
        const double* B = o.plain ? o.J : r.B[side];
        for (int p = 0; p < 6; ++p)
            o.u[p] = dot6(&bodies_[b].Hinv[6 * p], B);
        o.row = i;
        o.side = side;
        o.group = r.group;
        o.local = r.local;
        return o;
    }

    // the u of on_'s entries into u_, for dv once the system is solved
    void keep_u() {
        for (const On& o : on_) {
            double* u = &u_[12 * static_cast<size_t>(o.row) + 6 * o.side];
            for (int p = 0; p < 6; ++p)
                u[p] = o.u[p];
        }
    }

    // the system along chains (block tridiagonal, the groups of setup): its active rows'
    // dlambda; false where an entry falls outside the blocks
    bool solve_chain() {
        const size_t nrows = rows_.size();
        const int ngroups = static_cast<int>(order_.size());
        // the active rows by group
        group_active_.resize(static_cast<size_t>(ngroups));
        n_.assign(static_cast<size_t>(ngroups), 0);
        for (int g = 0; g < ngroups; ++g) {
            std::vector<int>& act = group_active_[g];
            act.clear();
            for (int i : group_rows_[g]) {
                if (rows_[i].state == kActive) {
                    rows_[i].local = static_cast<int>(act.size());
                    act.push_back(i);
                }
            }
            n_[g] = static_cast<int>(act.size());
        }
        // storage of the blocks
        d_off_.assign(ngroups + 1, 0);
        l_off_.assign(ngroups + 1, 0);
        v_off_.assign(ngroups + 1, 0);
        for (int g = 0; g < ngroups; ++g) {
            const size_t n = n_[g], p = g > 0 ? n_[g - 1] : 0;
            d_off_[g + 1] = d_off_[g] + n * n;
            l_off_[g + 1] = l_off_[g] + n * p;
            v_off_[g + 1] = v_off_[g] + n;
        }
        D_.assign(d_off_[ngroups], 0);
        L_.assign(l_off_[ngroups], 0);
        U_.assign(l_off_[ngroups], 0);  // U_g: n_{g-1} x n_g, same size as L_g
        X_.assign(l_off_[ngroups], 0);
        rhs_.assign(v_off_[ngroups], 0);
        piv_.assign(v_off_[ngroups], 0);
        u_.resize(nrows * 12);
        // S's entries, body by body: the active rows on it, u = H^-1 B' each, J_i . u_j
        // (symmetric where both rows' B is their J)
        bool fail = false;
        for (int b = 0; b < ngroups && !fail; ++b) {
            on_.clear();
            for (int i : body_rows_[b]) {
                Row& r = rows_[i];
                if (r.state != kActive) continue;
                on_.push_back(on_body(i, b));
            }
            const int m = static_cast<int>(on_.size());
            for (int x = 0; x < m; ++x) {
                const On& oi = on_[x];
                for (int y = 0; y < m; ++y) {
                    const On& oj = on_[y];
                    if (y < x && oi.plain && oj.plain) continue;  // added with (y, x)
                    const double v = dot6(oi.J, oj.u);
                    if (!add_entry(oi, oj, v)) fail = true;
                    if (y != x && oi.plain && oj.plain && !add_entry(oj, oi, v)) fail = true;
                }
            }
            keep_u();
        }
        if (fail) return false;
        // diagonal terms and right side
        for (int g = 0; g < ngroups; ++g) {
            for (int i : group_active_[g]) {
                const Row& r = rows_[i];
                double& d = D_[d_off_[g] + r.local * n_[g] + r.local];
                d += r.cfm + r.reg;
                // contact rows can be redundant (a box's four corners sticking)
                d += kNewtonRegulariser * std::fabs(d);
                double v = -r.w;
                for (int k = 0; k < r.nb; ++k)
                    v -= dot6(r.J[k], bodies_[r.body[k]].h);
                rhs_[v_off_[g] + r.local] = v;
            }
        }
        // block LU: D'_g = D_g - L_g D'_{g-1}^-1 U_g, forward substitution alongside
        for (int g = 0; g < ngroups; ++g) {
            const int n = n_[g];
            double* D = &D_[d_off_[g]];
            double* y = &rhs_[v_off_[g]];
            if (g > 0 && n_[g - 1] > 0 && n > 0) {
                const int p = n_[g - 1];
                double* X = &X_[l_off_[g]];
                const double* U = &U_[l_off_[g]];
                const double* L = &L_[l_off_[g]];
                for (size_t k = 0; k < static_cast<size_t>(p) * n; ++k)
                    X[k] = U[k];
                lu_solve(&D_[d_off_[g - 1]], &piv_[v_off_[g - 1]], p, X, n);
                const double* z = &rhs_[v_off_[g - 1]];  // already D'^-1 y
                for (int i = 0; i < n; ++i) {
                    for (int k = 0; k < p; ++k) {
                        const double l = L[i * p + k];
                        if (l == 0) continue;
                        for (int j = 0; j < n; ++j)
                            D[i * n + j] -= l * X[k * n + j];
                        y[i] -= l * z[k];
                    }
                }
            }
            if (n > 0) {
                lu(D, &piv_[v_off_[g]], n);
                lu_solve(D, &piv_[v_off_[g]], n, y, 1);
            }
        }
        for (int g = ngroups - 2; g >= 0; --g) {
            const int n = n_[g], m = n_[g + 1];
            if (n == 0 || m == 0) continue;
            const double* X = &X_[l_off_[g + 1]];
            double* x = &rhs_[v_off_[g]];
            const double* xn = &rhs_[v_off_[g + 1]];
            for (int i = 0; i < n; ++i) {
                double s = 0;
                for (int j = 0; j < m; ++j)
                    s += X[i * m + j] * xn[j];
                x[i] -= s;
            }
        }
        for (int g = 0; g < ngroups; ++g)
            for (int i : group_active_[g])
                rows_[i].dl = rhs_[v_off_[g] + rows_[i].local];
        return true;
    }

    // a row whose dlambda is an unknown of the linear system: an active row, or a row of a
    // sliding pair between two moving bodies (only the general structure has those)
    static bool in_system(const Row& r) {
        return r.state == kActive || (r.state == kSliding && r.nb == 2);
    }

    // the system of any structure (two moving bodies touching, branches, loops), sparse: its
    // rows are the active rows and the rows of sliding pairs between two moving bodies, whose
    // linearised F (A dlambda_t + r P J_t dv - s dlambda_n = -F_t, A = I - (1 - r g) P, P = a
    // perp perp') stays an equation of its own, as H cannot take it body by body. Eigen's
    // SparseLU (COLAMD ordering, partial pivoting): the same matrix gives the same answer
    // (newton_step.cpp: Eigen stays out of this header's includers)
    bool solve_general();

    void solve(btAlignedObjectArray<btSolverBody>& pool, int steps) {
        const size_t nrows = rows_.size();
        const int nbodies = static_cast<int>(bodies_.size());
        bool changed = false;
        for (int step = 0; step < steps; ++step) {
            // velocities, states, F
            for (Row& r : rows_)
                r.w = velocity(r) + r.cfm * r.lambda;
            for (size_t i = 0; i < nrows; ++i) {
                Row& r = rows_[i];
                r.local = -1;
                r.plainB = true;
                if (r.kind == kClamp) {
                    const double x = r.lambda - r.r * r.w;
                    if (x <= r.lo) {
                        r.state = kBound;
                        r.bound = r.lo;
                    } else if (x >= r.hi) {
                        r.state = kBound;
                        r.bound = r.hi;
                    } else {
                        r.state = kActive;
                    }
                } else if (r.kind == kFriction1) {
                    Row& r2 = rows_[i + 1];
                    const Row& rn = rows_[r.normal];
                    const double mu = r.c->m_friction;
                    const double rho = rn.lambda > 0 ? mu * rn.lambda : 0;
                    const double x1 = r.lambda - r.r * r.w, x2 = r2.lambda - r.r * r2.w;
                    const double len = std::sqrt(x1 * x1 + x2 * x2);
                    if (len <= rho) {
                        r.state = r2.state = kActive;
                    } else {
                        r.state = r2.state = kSliding;
                        const double a = rho / len, h1 = x1 / len, h2 = x2 / len;
                        // P = a (I - h h'); F = lambda - rho h
                        const double F1 = r.lambda - rho * h1, F2 = r2.lambda - rho * h2;
                        // with the pair's damping g (its reg, kNewtonFrictionDamping) taken as
                        // if dx = (1 - r g) dlambda - r J dv, A = I - (1 - r g) P takes I - P's
                        // place: A^-1 = h h' + (I - h h') / (1 - (1 - r g) a), E = r a / (1 - (1 -
                        // r g) a) (I - h h'), c = A^-1 (-F); A^-1 s = s
                        const double q = 1 / (1 - (1 - r.r * (r.cfm + r.reg)) * a);
                        const double p11 = 1 - h1 * h1, p12 = -h1 * h2, p22 = 1 - h2 * h2;
                        const double i11 = h1 * h1 + q * p11, i12 = h1 * h2 + q * p12,
                                     i22 = h2 * h2 + q * p22;
                        r.cvec[0] = -(i11 * F1 + i12 * F2);
                        r.cvec[1] = -(i12 * F1 + i22 * F2);
                        // E = e perp perp', perp = (-h2, h1): I - h h' = perp perp'
                        r.e = r.r * a * q;
                        r.perp[0] = -h2;
                        r.perp[1] = h1;
                        (void)p22;
                        const double slope = rn.lambda > 0 ? mu : 0;
                        r.s[0] = slope * h1;
                        r.s[1] = slope * h2;
                        r.a = a;
                        r.f[0] = F1;
                        r.f[1] = F2;
                    }
                }
            }
            const double f = std::sqrt(merit(0));
            if (!(f > 1e-14)) break;
            // per body: H^-1 (M^-1 updated by each sliding pair's rank-one term
            // e q q', q = J_t' perp: E = e perp perp', Sherman-Morrison), g, h = H^-1 g. A
            // sliding pair between two moving bodies is not eliminated: its rows are unknowns of
            // the system (solve_general)
            for (int b = 0; b < nbodies; ++b) {
                Body& body = bodies_[b];
                double* Hi = body.Hinv;
                for (int k = 0; k < 36; ++k)
                    Hi[k] = 0;
                for (int k = 0; k < 3; ++k)
                    Hi[7 * k] = body.inv_mass;
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j)
                        Hi[6 * (3 + i) + 3 + j] = body.inv_inertia[3 * i + j];
                double g[6] = {0, 0, 0, 0, 0, 0};
                for (int i : body_rows_[b]) {
                    Row& r = rows_[i];
                    const int side = r.body[0] == b ? 0 : 1;
                    if (r.kind == kFriction1 && r.state == kSliding && r.nb == 1) {
                        const Row& r2 = rows_[i + 1];
                        const Row& rn = rows_[r.normal];
                        const double* j1 = r.J[0];
                        const double* j2 = r2.J[0];
                        if (r.e > 0) {
                            double q[6], hq[6];
                            for (int p = 0; p < 6; ++p)
                                q[p] = j1[p] * r.perp[0] + j2[p] * r.perp[1];
                            double qhq = 0;
                            for (int p = 0; p < 6; ++p) {
                                hq[p] = dot6(&Hi[6 * p], q);
                                qhq += q[p] * hq[p];
                            }
                            const double k = r.e / (1 + r.e * qhq);
                            for (int p = 0; p < 6; ++p)
                                for (int c = 0; c < 6; ++c)
                                    Hi[6 * p + c] -= k * hq[p] * hq[c];
                        }
                        double c1 = r.cvec[0], c2 = r.cvec[1];
                        if (rn.state == kBound) {
                            const double dn = rn.bound - rn.lambda;
                            c1 += r.s[0] * dn;
                            c2 += r.s[1] * dn;
                        }
                        for (int p = 0; p < 6; ++p)
                            g[p] += j1[p] * c1 + j2[p] * c2;
                    } else if (r.kind == kClamp && r.state == kBound) {
                        const double d = r.bound - r.lambda;
                        for (int p = 0; p < 6; ++p)
                            g[p] += r.J[side][p] * d;
                    }
                }
                for (int p = 0; p < 6; ++p)
                    body.h[p] = dot6(&Hi[6 * p], g);
            }
            // pressed normals with a sliding pair: B = J_n + s' J_t
            for (size_t i = 0; i < nrows; ++i) {
                Row& r = rows_[i];
                if (r.kind != kFriction1 || r.state != kSliding || r.nb != 1) continue;
                Row& rn = rows_[r.normal];
                if (rn.state != kActive) continue;
                const Row& r2 = rows_[i + 1];
                rn.plainB = false;
                for (int p = 0; p < 6; ++p)
                    rn.B[0][p] = rn.J[0][p] + r.s[0] * r.J[0][p] + r.s[1] * r2.J[0][p];
            }
            // the system's rows' dlambda (the active rows; the rows of sliding pairs between two
            // moving bodies), and each of them's H^-1 B' on its bodies in u_
            if (!(general_ ? solve_general() : solve_chain())) break;
            // dv, the others' dlambda
            for (int b = 0; b < nbodies; ++b) {
                Body& body = bodies_[b];
                for (int p = 0; p < 6; ++p)
                    body.dv[p] = body.h[p];
                for (int i : body_rows_[b]) {
                    const Row& r = rows_[i];
                    if (!in_system(r)) continue;
                    const int side = r.body[0] == b ? 0 : 1;
                    const double* u = &u_[12 * i + 6 * side];
                    for (int p = 0; p < 6; ++p)
                        body.dv[p] += u[p] * r.dl;
                }
            }
            for (size_t i = 0; i < nrows; ++i) {
                Row& r = rows_[i];
                if (r.state == kBound) {
                    r.dl = r.bound - r.lambda;
                } else if (r.kind == kFriction1 && r.state == kSliding && r.nb == 1) {
                    Row& r2 = rows_[i + 1];
                    const Row& rn = rows_[r.normal];
                    const double* dv = bodies_[r.body[0]].dv;
                    const double jd1 = dot6(r.J[0], dv), jd2 = dot6(r2.J[0], dv);
                    const double ej = r.e * (r.perp[0] * jd1 + r.perp[1] * jd2);
                    r.dl = r.cvec[0] - ej * r.perp[0] + r.s[0] * rn.dl;
                    r2.dl = r.cvec[1] - ej * r.perp[1] + r.s[1] * rn.dl;
                }
            }
            // the bodies' change M^-1 J' dlambda and the rows' dw
            for (int b = 0; b < nbodies; ++b) {
                Body& body = bodies_[b];
                double imp[6] = {0, 0, 0, 0, 0, 0};
                for (int i : body_rows_[b]) {
                    const Row& r = rows_[i];
                    const int side = r.body[0] == b ? 0 : 1;
                    for (int p = 0; p < 6; ++p)
                        imp[p] += r.J[side][p] * r.dl;
                }
                minv(body, imp, body.dV);
            }
            bool finite = true;
            for (Row& r : rows_) {
                r.dw = r.cfm * r.dl;
                for (int k = 0; k < r.nb; ++k)
                    r.dw += dot6(r.J[k], bodies_[r.body[k]].dV);
                finite = finite && std::isfinite(r.dl) && std::isfinite(r.dw);
            }
            if (!finite) break;
            // line search on |F|
            const double f2 = f * f;
            double alpha = 1;
            bool accepted = false;
            for (int t = 0; t < 9; ++t) {
                if (merit(alpha) < f2) {
                    accepted = true;
                    break;
                }
                alpha *= 0.5;
            }
            if (!accepted) break;
            for (Row& r : rows_)
                r.lambda += alpha * r.dl;
            for (Body& body : bodies_)
                for (int p = 0; p < 6; ++p)
                    body.V[p] += alpha * body.dV[p];
            changed = true;
        }
        if (!changed) return;
        for (Row& r : rows_)
            r.c->m_appliedImpulse = static_cast<btScalar>(r.lambda);
        for (Body& body : bodies_) {
            btSolverBody& s = pool[body.solver];
            s.m_deltaLinearVelocity.setValue(static_cast<btScalar>(body.V[0]),
                                             static_cast<btScalar>(body.V[1]),
                                             static_cast<btScalar>(body.V[2]));
            s.m_deltaAngularVelocity.setValue(static_cast<btScalar>(body.V[3]),
                                              static_cast<btScalar>(body.V[4]),
                                              static_cast<btScalar>(body.V[5]));
        }
    }
};

}  // namespace gaitlab
