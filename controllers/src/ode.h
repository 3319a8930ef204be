// Shared pieces of the oscillator controllers: a fixed-step RK4 integrator and seeded initial
// states. Private to controllers/src.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace gaitlab::controllers::detail {

/// Longest integration sub-step, s. The oscillators run at a few Hz with time constants of
/// 50 ms or more, so RK4 at 5 ms keeps phases within about 1e-6 deg of the exact solution per
/// second (the tests measure it) and the result barely depends on the control period (which is
/// split into equal sub-steps no longer than this). 1 ms cost 4% of a physics step for an
/// 8-joint phase_chain at control_every = 10; 5 ms costs a fifth of that.
constexpr double kMaxSubstep = 0.005;

/// Number of equal sub-steps that cover `dt` with none longer than kMaxSubstep.
inline int substeps(double dt) {
    const double n = std::ceil(dt / kMaxSubstep - 1e-9);
    return std::max(1, static_cast<int>(n));
}

/// Classic fourth-order Runge-Kutta on a state vector; keeps its scratch space between calls.
class Rk4 {
  public:
    /// Advances `x` by `dt` in substeps(dt) steps; `f(x, dxdt)` writes the derivative.
    template <class F>
    void integrate(std::vector<double>& x, double dt, F&& f) {
        integrate(x, dt, kMaxSubstep, f, [](const std::vector<double>&, double) {});
    }

    /// Advances `x` by `dt` in equal sub-steps no longer than `max_step`, calling
    /// `after(x, h)` after each sub-step of length h.
    template <class F, class G>
    void integrate(std::vector<double>& x, double dt, double max_step, F&& f, G&& after) {
        const double n_steps = std::ceil(dt / max_step - 1e-9);
        const int n = std::max(1, static_cast<int>(n_steps));
        const double h = dt / n;
        for (int i = 0; i < n; ++i) {
            step(x, h, f);
            after(x, h);
        }
    }

  private:
    template <class F>
    void step(std::vector<double>& x, double h, F& f) {
        const size_t n = x.size();
        k1_.resize(n);
        k2_.resize(n);
        k3_.resize(n);
        k4_.resize(n);
        tmp_.resize(n);
        f(x, k1_);
        for (size_t i = 0; i < n; ++i)
            tmp_[i] = x[i] + 0.5 * h * k1_[i];
        f(tmp_, k2_);
        for (size_t i = 0; i < n; ++i)
            tmp_[i] = x[i] + 0.5 * h * k2_[i];
        f(tmp_, k3_);
        for (size_t i = 0; i < n; ++i)
            tmp_[i] = x[i] + h * k3_[i];
        f(tmp_, k4_);
        for (size_t i = 0; i < n; ++i)
            x[i] += h / 6 * (k1_[i] + 2 * k2_[i] + 2 * k3_[i] + k4_[i]);
    }

    std::vector<double> k1_, k2_, k3_, k4_, tmp_;
};

/// A number in [0, 1) that depends only on `seed` and `index` (SplitMix64), the same on every
/// platform, unlike the standard library's distributions.
inline double seeded_unit(std::uint64_t seed, std::uint64_t index) {
    std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + index + 1;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z = z ^ (z >> 31);
    return static_cast<double>(z >> 11) * 0x1.0p-53;
}

/// Initial phase of oscillator m, rad: 0 for seed 0, else uniform in [0, 2 pi) from the seed.
inline double initial_phase(double seed, int m) {
    if (seed <= 0) return 0;
    const double two_pi = 6.283185307179586;
    return two_pi * seeded_unit(static_cast<std::uint64_t>(seed), static_cast<std::uint64_t>(m));
}

/// `rad` wrapped into [0, 2 pi).
inline double wrap_phase(double rad) {
    const double two_pi = 6.283185307179586;
    const double w = std::fmod(rad, two_pi);
    const double out = w < 0 ? w + two_pi : w;
    return out < two_pi ? out : 0;
}

}  // namespace gaitlab::controllers::detail
