// L D L' of a symmetric matrix kept on its profile, for CoulombSolver's block methods
// (coulomb_solver.h) when the joints' rows are not a chain of hinges (block_band.h is the chain's
// faster form, and takes every sum in the order these do, so both give the same bits). The
// matrix's row i has no entries left of column first[i], and neither has its factor: only the
// profile is kept (below). Eigen's sparse LDL' would do the same with a
// fill-reducing ordering, which changes the order of the sums and so the bits of every
// block_nncg run; a dozen lines keep them.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>

namespace gaitlab {

// The profile's storage: row i keeps its columns first[i] .. i, at l[start[i] + j - first[i]]
// (start[i + 1] = start[i] + i - first[i] + 1), so a tree of thousands of bodies takes the
// entries its rows hold, not n x n doubles (a 2000-body robot with one branch took 1.2 GB).

/// Factors `l` (holding K's profile on entry, L's strict lower part on return; L's unit
/// diagonal is not stored) and writes D to `diag`. A row whose pivot vanishes (a redundant row:
/// a closed loop of joints makes K singular) keeps `own(i)` as its pivot, as a row solved alone
/// would. Returns the smallest pivot over its row's own(i) (infinity for n = 0): below 1e-9
/// where a pivot fell to it; a small one says how much of the row cancelled. Each row's pivot
/// over own(i) also goes to ratios[i] where `ratios` is given.
template <class Own>
double profile_factor(double* l, const std::size_t* start, double* diag, const int* first, int n,
                      Own own, double* ratios = nullptr) {
    double least = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) {
        // column j of row i at l[row + j] (unsigned: the offsets wrap back into the row)
        const std::size_t row = start[i] - static_cast<std::size_t>(first[i]);
        for (int j = first[i]; j <= i; ++j) {
            const std::size_t other = start[j] - static_cast<std::size_t>(first[j]);
            double sum = l[row + j];
            for (int k = std::max(first[i], first[j]); k < j; ++k)
                sum -= l[row + k] * l[other + k] * diag[k];
            if (j < i) {
                l[row + j] = sum / diag[j];
            } else {
                const double pivot = own(i);
                const double ratio = sum / pivot;
                if (!(ratio >= least)) least = ratio;  // and a NaN stays
                if (ratios) ratios[i] = ratio;
                diag[i] = sum > 1e-9 * pivot ? sum : pivot;
            }
        }
    }
    return least;
}

/// L y = r, D z = y, L' x = z, in place in `x` (r on entry, x on return).
inline void profile_substitute(const double* l, const std::size_t* start, const double* diag,
                               const int* first, int n, double* x) {
    for (int i = 0; i < n; ++i) {
        double sum = x[i];
        const std::size_t row = start[i] - static_cast<std::size_t>(first[i]);
        for (int k = first[i]; k < i; ++k)
            sum -= l[row + k] * x[k];
        x[i] = sum;
    }
    for (int i = 0; i < n; ++i)
        x[i] /= diag[i];
    for (int k = n - 1; k > 0; --k) {  // x_k is final: take it out of the rows above
        const double xk = x[k];
        const std::size_t row = start[k] - static_cast<std::size_t>(first[k]);
        for (int j = first[k]; j < k; ++j)
            x[j] -= l[row + j] * xk;
    }
}

}  // namespace gaitlab
