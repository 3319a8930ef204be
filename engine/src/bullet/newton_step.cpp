// NewtonStep's linear system for any structure (newton_step.h): Eigen's sparse LU, kept out of
// the header, which the solver's includers read
#include "newton_step.h"

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <array>
#include <vector>

namespace gaitlab {

bool NewtonStep::solve_general() {
    const size_t nrows = rows_.size();
    const int nbodies = static_cast<int>(bodies_.size());
    sys_.clear();
    for (size_t i = 0; i < nrows; ++i) {
        Row& r = rows_[i];
        if (!in_system(r)) continue;
        r.local = static_cast<int>(sys_.size());
        sys_.push_back(static_cast<int>(i));
    }
    const int n = static_cast<int>(sys_.size());
    if (n == 0) return true;
    diag_.assign(static_cast<size_t>(n), 0);
    std::vector<Eigen::Triplet<double>> triplets;
    u_.resize(nrows * 12);
    // S's entries, body by body: left_i . u_j for the system's rows on it, u = H^-1 B'; a
    // sliding pair's rows' left is r P J_t (the pair's first row holds a and perp)
    std::vector<std::array<double, 6>> left;
    for (int b = 0; b < nbodies; ++b) {
        on_.clear();
        left.clear();
        for (int i : body_rows_[b]) {
            const Row& r = rows_[i];
            if (!in_system(r)) continue;
            const On o = on_body(i, b);
            on_.push_back(o);
            const int side = o.side;
            std::array<double, 6> l;
            if (r.state == kSliding) {
                const int first = r.kind == kFriction1 ? i : i - 1;
                const Row& r1 = rows_[first];
                const Row& r2 = rows_[first + 1];
                const double k = r1.r * r1.a * r1.perp[r.kind == kFriction1 ? 0 : 1];
                for (int p = 0; p < 6; ++p)
                    l[p] = k * (r1.perp[0] * r1.J[side][p] + r1.perp[1] * r2.J[side][p]);
            } else {
                for (int p = 0; p < 6; ++p)
                    l[p] = o.J[p];
            }
            left.push_back(l);
        }
        const int m = static_cast<int>(on_.size());
        for (int x = 0; x < m; ++x)
            for (int y = 0; y < m; ++y) {
                const double v = dot6(left[x].data(), on_[y].u);
                if (on_[x].local == on_[y].local) {
                    diag_[on_[x].local] += v;
                } else {
                    triplets.emplace_back(on_[x].local, on_[y].local, v);
                }
            }
        keep_u();
    }
    // diagonal terms and right side
    Eigen::VectorXd rhs(n);
    for (int x = 0; x < n; ++x) {
        const int i = sys_[x];
        const Row& r = rows_[i];
        double d = diag_[x], v;
        if (r.state == kActive) {
            d += r.cfm + r.reg;
            d += kNewtonRegulariser * std::fabs(d);
            v = -r.w;
            for (int k = 0; k < r.nb; ++k)
                v -= dot6(r.J[k], bodies_[r.body[k]].h);
        } else {
            const int first = r.kind == kFriction1 ? i : i - 1, k = i - first;
            const Row& r1 = rows_[first];
            const Row& rn = rows_[r1.normal];
            // A = I - (1 - r reg) P, as a one-body pair's (solve)
            const double c = (1 - r1.r * (r1.cfm + r1.reg)) * r1.a;
            d += 1 - c * r1.perp[k] * r1.perp[k];
            triplets.emplace_back(x, rows_[first + 1 - k].local, -c * r1.perp[k] * r1.perp[1 - k]);
            v = -r1.f[k];
            const Row& r2 = rows_[first + 1];
            const double scale = r1.r * r1.a * r1.perp[k];
            for (int side = 0; side < 2; ++side) {
                const double* h = bodies_[r1.body[side]].h;
                v -= scale * (r1.perp[0] * dot6(r1.J[side], h) + r1.perp[1] * dot6(r2.J[side], h));
            }
            if (rn.state == kActive) {
                triplets.emplace_back(x, rn.local, -r1.s[k]);
            } else {
                v += r1.s[k] * (rn.bound - rn.lambda);
            }
        }
        triplets.emplace_back(x, x, d);
        rhs[x] = v;
    }
    Eigen::SparseMatrix<double> S(n, n);
    S.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
    lu.compute(S);
    if (lu.info() != Eigen::Success) return false;
    const Eigen::VectorXd dl = lu.solve(rhs);
    if (lu.info() != Eigen::Success) return false;
    for (int x = 0; x < n; ++x)
        rows_[sys_[x]].dl = dl[x];
    return true;
}

}  // namespace gaitlab
