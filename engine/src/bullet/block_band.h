// The joints' rows of CoulombSolver's block methods (coulomb_solver.h) when they form a chain of
// hinges: groups of kBandRows slots, a hinge's 5 rows without bounds and its motor's row (the
// sixth slot, empty where the hinge has no motor row or its motor is at its torque limit), each
// group coupled through K = J M^-1 J' only to itself and to the group before it (the hinge before
// it along the chain, which shares a body with it). K is then block tridiagonal and so are its
// factors: L D L' is kept as two kBandRows x kBandRows blocks per group, and the substitutions
// run over fixed-size blocks without the profile's indexing (docs/performance.md, "Converging
// the solve"). An empty slot has no couplings and a diagonal of 1, so its solution is 0 and it
// changes no other row's: every sum is taken in the order of the profile's factor and
// substitutions (CoulombSolver::factor_block, solve_block), which leave the empty slots out, and
// both give the same bits.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <limits>

namespace gaitlab {

inline constexpr int kBandRows = 6;

struct BandGroup {
    /// before band_factor: K within the group below the diagonal; after: L there
    double lower[kBandRows][kBandRows];
    /// before band_factor: K against the previous group's rows; after: L there (if coupled)
    double prev[kBandRows][kBandRows];
    /// before band_factor: K's diagonal; after: D
    double diag[kBandRows];
    /// each row's own diagonal 1 / jacDiagABInv, kept where K is singular (redundant rows)
    double own[kBandRows];
    /// whether the group shares a moving body with the previous one
    bool coupled;
};

/// L D L' of the block tridiagonal K, in place (as CoulombSolver's profile factor: row by row,
/// each row's columns left to right, each sum over k ascending). Returns the smallest pivot
/// over its row's own diagonal (profile_factor's `least`): below 1e-9 a pivot fell to that
/// diagonal, and as no row of a chain is redundant, K as given was not positive definite and
/// the factor is not its own; a small one says how much of the row cancelled, and so how few
/// of its entries' digits the factor kept (CoulombSolver::band_matrix).
inline double band_factor(BandGroup* g, int count) {
    double least = std::numeric_limits<double>::infinity();
    for (int b = 0; b < count; ++b) {
        BandGroup& x = g[b];
        const BandGroup* p = b > 0 && x.coupled ? &g[b - 1] : nullptr;
        for (int r = 0; r < kBandRows; ++r) {
            if (p) {
#pragma GCC unroll 6
                for (int c = 0; c < kBandRows; ++c) {
                    double sum = x.prev[r][c];
#pragma GCC unroll 6
                    for (int k = 0; k < c; ++k)
                        sum -= x.prev[r][k] * p->lower[c][k] * p->diag[k];
                    x.prev[r][c] = sum / p->diag[c];
                }
            }
            for (int c = 0; c <= r; ++c) {
                double sum = c < r ? x.lower[r][c] : x.diag[r];
                if (p) {
#pragma GCC unroll 6
                    for (int k = 0; k < kBandRows; ++k)
                        sum -= x.prev[r][k] * x.prev[c][k] * p->diag[k];
                }
#pragma GCC unroll 6
                for (int k = 0; k < c; ++k)
                    sum -= x.lower[r][k] * x.lower[c][k] * x.diag[k];
                if (c < r) {
                    x.lower[r][c] = sum / x.diag[c];
                } else {
                    // redundant rows make K singular: such a row keeps its own diagonal
                    const double ratio = sum / x.own[r];
                    if (!(ratio >= least)) least = ratio;  // and a NaN stays
                    x.diag[r] = sum > 1e-9 * x.own[r] ? sum : x.own[r];
                }
            }
        }
    }
    return least;
}

/// Solves L D L' v = rhs in place (v, rhs: kBandRows values per group): L y = rhs row by
/// row, then each row's v = y / D less the rows after it, nearest last, as the profile's
/// column-wise back substitution subtracts them.
inline void band_solve(const BandGroup* g, int count, double* v) {
    for (int b = 0; b < count; ++b) {
        const BandGroup& x = g[b];
        double* y = v + b * kBandRows;
        const double* yp = y - kBandRows;
        const bool coupled = b > 0 && x.coupled;
#pragma GCC unroll 6
        for (int r = 0; r < kBandRows; ++r) {
            double sum = y[r];
            if (coupled) {
#pragma GCC unroll 6
                for (int c = 0; c < kBandRows; ++c)
                    sum -= x.prev[r][c] * yp[c];
            }
#pragma GCC unroll 6
            for (int c = 0; c < r; ++c)
                sum -= x.lower[r][c] * y[c];
            y[r] = sum;
        }
    }
    for (int b = count - 1; b >= 0; --b) {
        const BandGroup& x = g[b];
        double* y = v + b * kBandRows;
        const double* yn = y + kBandRows;
        const BandGroup* next = b + 1 < count && g[b + 1].coupled ? &g[b + 1] : nullptr;
#pragma GCC unroll 6
        for (int r = kBandRows - 1; r >= 0; --r) {
            double sum = y[r] / x.diag[r];
            if (next) {
#pragma GCC unroll 6
                for (int k = kBandRows - 1; k >= 0; --k)
                    sum -= next->prev[k][r] * yn[k];
            }
#pragma GCC unroll 6
            for (int k = kBandRows - 1; k > r; --k)
                sum -= x.lower[k][r] * y[k];
            y[r] = sum;
        }
    }
}

// Four floats in one register (GCC's and Clang's vector extension; lane by lane the same IEEE
// operations as the scalar code, so the same bits). The right side and the impulses' effect on
// the bodies below run over a group's rows or a body's x, y, z at once.
using BandV4 = float __attribute__((vector_size(16)));

inline BandV4 band_v4(const btVector3& v) {
    return BandV4{v.m_floats[0], v.m_floats[1], v.m_floats[2], v.m_floats[3]};
}

inline void band_store3(btVector3& v, BandV4 x) {
    v.m_floats[0] = x[0];
    v.m_floats[1] = x[1];
    v.m_floats[2] = x[2];
}

/// A group's rows as the solve reads them, copied from their btSolverConstraint once per step,
/// lane k of half h being row 4 h + k (rows 6 and 7, and an empty slot, all zero with a
/// jacDiagABInv of 1): J (the normals and the arms' cross products of both bodies: x, y, z
/// each), rhs, cfm and jacDiagABInv; per row M^-1 J' of each body (the linear part as
/// CoulombSolver::apply computes it, the normal times the inverse mass).
struct BandRows {
    BandV4 jac[12][2];
    BandV4 rhs[2], cfm[2], inv[2];
    BandV4 lin_a[kBandRows], ang_a[kBandRows], lin_b[kBandRows], ang_b[kBandRows];
    int row[kBandRows];  // in the joint pool; -1: an empty slot
    int a, b;            // solver bodies
};

/// `rows[r]` null: slot r is empty
inline void band_rows(BandRows& g, const btSolverConstraint* const* rows,
                      const btAlignedObjectArray<btSolverBody>& bodies) {
    for (auto& j : g.jac)
        j[0] = j[1] = BandV4{0, 0, 0, 0};
    for (int h = 0; h < 2; ++h) {
        g.rhs[h] = g.cfm[h] = BandV4{0, 0, 0, 0};
        g.inv[h] = BandV4{1, 1, 1, 1};
    }
    for (int r = 0; r < kBandRows; ++r) {
        if (!rows[r]) {
            g.lin_a[r] = g.ang_a[r] = g.lin_b[r] = g.ang_b[r] = BandV4{0, 0, 0, 0};
            continue;
        }
        const btSolverConstraint& c = *rows[r];
        const btSolverBody& a = bodies[c.m_solverBodyIdA];
        const btSolverBody& b = bodies[c.m_solverBodyIdB];
        const btVector3* parts[4] = {&c.m_contactNormal1, &c.m_relpos1CrossNormal,
                                     &c.m_contactNormal2, &c.m_relpos2CrossNormal};
        const int h = r / 4, lane = r % 4;
        for (int p = 0; p < 4; ++p) {
            for (int k = 0; k < 3; ++k)
                g.jac[3 * p + k][h][lane] = parts[p]->m_floats[k];
        }
        g.rhs[h][lane] = c.m_rhs;
        g.cfm[h][lane] = c.m_cfm;
        g.inv[h][lane] = c.m_jacDiagABInv;
        g.lin_a[r] = band_v4(c.m_contactNormal1 * a.internalGetInvMass());
        g.ang_a[r] = band_v4(c.m_angularComponentA);
        g.lin_b[r] = band_v4(c.m_contactNormal2 * b.internalGetInvMass());
        g.ang_b[r] = band_v4(c.m_angularComponentB);
    }
}

/// A joint row for K's entries in double (CoulombSolver::band_matrix, profile_matrix): per body
/// (its A and B) the row's normal n and arm a = r x n, and what they do to that body: n over its
/// mass and W a, W the body's inverse inertia in world axes made symmetric, all in double.
/// K = J W J' is then positive definite to double's rounding, where entries taken in float, each
/// off by float's rounding of itself, are not once K's smallest eigenvalue is below float's
/// rounding of its largest (a chain of about a thousand hinges).
struct PreciseRow {
    double n[2][3], arm[2][3];
    double lin[2][3], ang[2][3];
};

/// `row` null: an empty slot (all zero); `a`, `b` its solver bodies
inline void precise_row(PreciseRow& p, const btSolverConstraint* row, const btSolverBody& a,
                        const btSolverBody& b) {
    const btSolverBody* body[2] = {&a, &b};
    const btVector3 zero(0, 0, 0);
    for (int s = 0; s < 2; ++s) {
        const btRigidBody* rigid = body[s]->m_originalBody;  // none: a fixed body
        const btMatrix3x3 w =
            rigid ? rigid->getInvInertiaTensorWorld() : btMatrix3x3(0, 0, 0, 0, 0, 0, 0, 0, 0);
        const btVector3& n = !row ? zero : s == 0 ? row->m_contactNormal1 : row->m_contactNormal2;
        const btVector3& arm = !row     ? zero
                               : s == 0 ? row->m_relpos1CrossNormal
                                        : row->m_relpos2CrossNormal;
        for (int i = 0; i < 3; ++i) {
            p.n[s][i] = n[i];
            p.arm[s][i] = arm[i];
            p.lin[s][i] = double(n[i]) * double(body[s]->m_invMass[i]);
        }
        for (int i = 0; i < 3; ++i) {
            double sum = 0;
            for (int j = 0; j < 3; ++j)
                sum += (double(w[i][j]) + double(w[j][i])) / 2 * p.arm[s][j];
            p.ang[s][i] = sum;
        }
    }
}

/// J_x W J_y' in double for row x (bodies xa, xb) and row y (bodies ya, yb), over the bodies
/// they share, x's first body first
inline double precise_coupling(const PreciseRow& x, int xa, int xb, const PreciseRow& y, int ya,
                               int yb) {
    double sum = 0;
    auto side = [&](int s, int body) {
        for (int t = 0; t < 2; ++t) {
            if ((t == 0 ? ya : yb) != body) continue;
            for (int i = 0; i < 3; ++i)
                sum += x.n[s][i] * y.lin[t][i] + x.arm[s][i] * y.ang[t][i];
        }
    };
    side(0, xa);
    if (xb != xa) side(1, xb);
    return sum;
}

/// a group's rows in double, slot by slot
struct BandPrecise {
    PreciseRow row[kBandRows];
};

inline btScalar band_dot(const btVector3& x, BandV4 y) {
    return x.m_floats[0] * y[0] + x.m_floats[1] * y[1] + x.m_floats[2] * y[2];
}

/// J_x M^-1 J_y' for row x and row c of group g, as CoulombSolver::coupling computes it (over
/// the bodies they share, x's first body first), from the group's M^-1 J'
inline btScalar band_coupling(const btSolverConstraint& x, const BandRows& g, int c) {
    btScalar sum = 0;
    auto side = [&](int body, const btVector3& lin, const btVector3& ang) {
        if (g.a == body) sum += band_dot(lin, g.lin_a[c]) + band_dot(ang, g.ang_a[c]);
        if (g.b == body) sum += band_dot(lin, g.lin_b[c]) + band_dot(ang, g.ang_b[c]);
    };
    side(x.m_solverBodyIdA, x.m_contactNormal1, x.m_relpos1CrossNormal);
    if (x.m_solverBodyIdB != x.m_solverBodyIdA)
        side(x.m_solverBodyIdB, x.m_contactNormal2, x.m_relpos2CrossNormal);
    return sum;
}

/// The right side of a group's rows (CoulombSolver::solve_block's, the change each row's own
/// update would make over its diagonal, given the bodies' velocities now) into out[0..5] (0 for
/// an empty slot).
inline void band_rhs(const BandRows& g, const btSolverConstraint* pool, const btSolverBody* bodies,
                     double* out) {
    const float* al = bodies[g.a].m_deltaLinearVelocity.m_floats;
    const float* aa = bodies[g.a].m_deltaAngularVelocity.m_floats;
    const float* bl = bodies[g.b].m_deltaLinearVelocity.m_floats;
    const float* ba = bodies[g.b].m_deltaAngularVelocity.m_floats;
    const auto& j = g.jac;
    BandV4 r[2];
#pragma GCC unroll 2
    for (int h = 0; h < 2; ++h) {
        // J v: each dot x + y + z, the four added in order, as CoulombSolver::row_velocity
        const BandV4 velocity = (j[0][h] * al[0] + j[1][h] * al[1] + j[2][h] * al[2]) +
                                (j[3][h] * aa[0] + j[4][h] * aa[1] + j[5][h] * aa[2]) +
                                (j[6][h] * bl[0] + j[7][h] * bl[1] + j[8][h] * bl[2]) +
                                (j[9][h] * ba[0] + j[10][h] * ba[1] + j[11][h] * ba[2]) -
                                g.rhs[h] / g.inv[h];
        BandV4 impulse = {0, 0, 0, 0};
        if (h == 0) {
            impulse[0] = pool[g.row[0]].m_appliedImpulse;
            impulse[1] = pool[g.row[1]].m_appliedImpulse;
            impulse[2] = pool[g.row[2]].m_appliedImpulse;
            impulse[3] = pool[g.row[3]].m_appliedImpulse;
        } else {
            impulse[0] = pool[g.row[4]].m_appliedImpulse;
            if (g.row[5] >= 0) impulse[1] = pool[g.row[5]].m_appliedImpulse;
        }
        r[h] = (g.rhs[h] - impulse * g.cfm[h]) / g.inv[h] - (velocity + g.rhs[h] / g.inv[h]);
    }
    out[0] = r[0][0];
    out[1] = r[0][1];
    out[2] = r[0][2];
    out[3] = r[0][3];
    out[4] = r[1][0];
    out[5] = r[1][1];
}

/// Applies the group's impulses d[0..5] (the solve's, in double) to its rows and bodies, row by
/// row as CoulombSolver::apply does (bodies whose linear and angular factors are 1), an empty
/// slot left out; returns the largest squared velocity change, as solve_block does.
inline btScalar band_apply(const BandRows& g, btSolverConstraint* pool, btSolverBody* bodies,
                           const double* d, btScalar residual) {
    btVector3& al = bodies[g.a].m_deltaLinearVelocity;
    btVector3& aa = bodies[g.a].m_deltaAngularVelocity;
    btVector3& bl = bodies[g.b].m_deltaLinearVelocity;
    btVector3& ba = bodies[g.b].m_deltaAngularVelocity;
    BandV4 xal = band_v4(al), xaa = band_v4(aa), xbl = band_v4(bl), xba = band_v4(ba);
#pragma GCC unroll 6
    for (int r = 0; r < kBandRows; ++r) {
        if (g.row[r] < 0) continue;
        const btScalar impulse = static_cast<btScalar>(d[r]);
        xal += g.lin_a[r] * impulse;
        xaa += g.ang_a[r] * impulse;
        xbl += g.lin_b[r] * impulse;
        xba += g.ang_b[r] * impulse;
        btSolverConstraint& c = pool[g.row[r]];
        c.m_appliedImpulse += impulse;
        residual = btMax(residual, impulse * impulse / (c.m_jacDiagABInv * c.m_jacDiagABInv));
    }
    // x, y, z only: btVector3's own arithmetic leaves the fourth float alone
    band_store3(al, xal);
    band_store3(aa, xaa);
    band_store3(bl, xbl);
    band_store3(ba, xba);
    return residual;
}

}  // namespace gaitlab
