// L D L' of a symmetric matrix kept on its profile, for CoulombSolver's block methods
// (coulomb_solver.h) when the joints' rows are not a chain of hinges (block_band.h is the chain's
// faster form, and takes every sum in the order these do, so both give the same bits). The
// matrix is row-major n x n; row i has no entries left of column first[i], and neither has its
// factor: only the profile is read and written. Eigen's sparse LDL' would do the same with a
// fill-reducing ordering, which changes the order of the sums and so the bits of every
// block_nncg run; a dozen lines keep them.
#pragma once

#include <algorithm>
#include <cstddef>

namespace gaitlab {

/// Factors `l` (holding K on entry, L's strict lower part on return; L's unit diagonal is not
/// stored) and writes D to `diag`. A row whose pivot vanishes (a redundant row: a closed loop of
/// joints makes K singular) keeps `own(i)` as its pivot, as a row solved alone would.
template <class Own>
void profile_factor(double* l, double* diag, const int* first, int n, Own own) {
    for (int i = 0; i < n; ++i) {
        for (int j = first[i]; j <= i; ++j) {
            double sum = l[static_cast<std::size_t>(i) * n + j];
            for (int k = std::max(first[i], first[j]); k < j; ++k)
                sum -= l[static_cast<std::size_t>(i) * n + k] *
                       l[static_cast<std::size_t>(j) * n + k] * diag[k];
            if (j < i) {
                l[static_cast<std::size_t>(i) * n + j] = sum / diag[j];
            } else {
                const double pivot = own(i);
                diag[i] = sum > 1e-9 * pivot ? sum : pivot;
            }
        }
    }
}

/// L y = r, D z = y, L' x = z, in place in `x` (r on entry, x on return).
inline void profile_substitute(const double* l, const double* diag, const int* first, int n,
                               double* x) {
    for (int i = 0; i < n; ++i) {
        double sum = x[i];
        const double* row = l + static_cast<std::size_t>(i) * n;
        for (int k = first[i]; k < i; ++k)
            sum -= row[k] * x[k];
        x[i] = sum;
    }
    for (int i = 0; i < n; ++i)
        x[i] /= diag[i];
    for (int k = n - 1; k > 0; --k) {  // x_k is final: take it out of the rows above
        const double xk = x[k];
        const double* row = l + static_cast<std::size_t>(k) * n;
        for (int j = first[k]; j < k; ++j)
            x[j] -= row[j] * xk;
    }
}

}  // namespace gaitlab
