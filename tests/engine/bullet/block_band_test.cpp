// The block tridiagonal factor of a chain of hinges' rows (engine/src/bullet/block_band.h):
// it solves K x = r, and gives the same bits as the L D L' on K's profile that CoulombSolver
// uses for other structures (the same sums in the same order).
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "bullet/block_band.h"
#include "bullet/profile_ldl.h"

namespace {

using gaitlab::BandGroup;
using gaitlab::kBandRows;
using gaitlab::profile_factor;
using gaitlab::profile_substitute;

// a chain's K: J M^-1 J' of random rows, each group's 5 rows on bodies g and g + 1 (6 numbers
// per body), so each group couples to the one before it through body g
struct Chain {
    int groups = 0;
    std::vector<double> k;  // n x n, row-major
    std::vector<bool> coupled;
    int n() const { return groups * kBandRows; }
};

Chain make_chain(int groups, unsigned seed, int uncoupled_at = -1) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    const int n = groups * kBandRows, bodies = groups + 1, dof = 6;
    std::vector<double> j(static_cast<size_t>(n) * bodies * dof, 0.0);
    for (int g = 0; g < groups; ++g) {
        for (int r = 0; r < kBandRows; ++r) {
            for (int b : {g, g + 1}) {
                if (b == g && g == uncoupled_at) continue;  // a fixed body: no coupling back
                for (int d = 0; d < dof; ++d)
                    j[(static_cast<size_t>(g * kBandRows + r) * bodies + b) * dof + d] = u(rng);
            }
        }
    }
    Chain c;
    c.groups = groups;
    c.k.assign(static_cast<size_t>(n) * n, 0.0);
    for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) {
            double sum = 0;
            for (int x = 0; x < bodies * dof; ++x)
                sum += j[static_cast<size_t>(a) * bodies * dof + x] *
                       j[static_cast<size_t>(b) * bodies * dof + x];
            c.k[static_cast<size_t>(a) * n + b] = sum + (a == b ? 0.01 : 0.0);
        }
    }
    for (int g = 0; g < groups; ++g)
        c.coupled.push_back(g > 0 && g != uncoupled_at);
    return c;
}

std::vector<BandGroup> band_of(const Chain& c) {
    std::vector<BandGroup> band(c.groups);
    const int n = c.n();
    for (int g = 0; g < c.groups; ++g) {
        BandGroup& b = band[g];
        b.coupled = c.coupled[g];
        for (int r = 0; r < kBandRows; ++r) {
            const int i = g * kBandRows + r;
            for (int col = 0; col < kBandRows; ++col) {
                if (b.coupled)
                    b.prev[r][col] = c.k[static_cast<size_t>(i) * n + i - r - kBandRows + col];
                if (col < r) b.lower[r][col] = c.k[static_cast<size_t>(i) * n + i - r + col];
            }
            b.diag[r] = c.k[static_cast<size_t>(i) * n + i];
            b.own[r] = b.diag[r];
        }
    }
    return band;
}

// CoulombSolver's profile factor and substitutions (profile_ldl.h, as factor_block and
// profile_solve call them)
std::vector<double> profile_solve(const Chain& c, std::vector<double> x) {
    const int n = c.n();
    std::vector<double> diag(n), l;
    std::vector<int> first(n);
    std::vector<size_t> start(n + 1, 0);
    for (int i = 0; i < n; ++i) {
        const int g = i / kBandRows;
        first[i] = c.coupled[g] ? (g - 1) * kBandRows : g * kBandRows;
        start[i + 1] = start[i] + static_cast<size_t>(i - first[i] + 1);
        for (int j = first[i]; j <= i; ++j)  // the profile of row i, as factor_block keeps it
            l.push_back(c.k[static_cast<size_t>(i) * n + j]);
    }
    // no pivot fell to its row's own diagonal
    CHECK(profile_factor(l.data(), start.data(), diag.data(), first.data(), n,
                         [&](int i) { return c.k[static_cast<size_t>(i) * n + i]; }) > 1e-9);
    profile_substitute(l.data(), start.data(), diag.data(), first.data(), n, x.data());
    return x;
}

}  // namespace

TEST_CASE("the band's factor solves a chain's K x = r, bit for bit as the profile does") {
    for (int uncoupled : {-1, 3}) {
        const Chain c = make_chain(8, 7u + static_cast<unsigned>(uncoupled + 1), uncoupled);
        const int n = c.n();
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> u(-1, 1);
        std::vector<double> r(n);
        for (double& v : r)
            v = u(rng);
        std::vector<BandGroup> band = band_of(c);
        gaitlab::band_factor(band.data(), c.groups);
        std::vector<double> x = r;
        gaitlab::band_solve(band.data(), c.groups, x.data());
        double worst = 0;
        for (int i = 0; i < n; ++i) {
            double kx = 0;
            for (int j = 0; j < n; ++j)
                kx += c.k[static_cast<size_t>(i) * n + j] * x[j];
            worst = std::max(worst, std::abs(kx - r[i]));
        }
        CHECK(worst < 1e-9);
        const std::vector<double> profile = profile_solve(c, r);
        for (int i = 0; i < n; ++i)
            CHECK(x[i] == profile[i]);  // the same sums in the same order
    }
}
