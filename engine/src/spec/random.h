// The random numbers of world generation (rubble fields): SplitMix64, whose sequence is fixed by
// its seed on every platform and standard library (std::uniform_real_distribution is not).
#pragma once

#include <cstdint>

namespace gaitlab::detail {

class SplitMix64 {
  public:
    explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }

    /// Uniform in [lo, hi), from the top 53 bits.
    double uniform(double lo, double hi) {
        const double u = static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0);
        return lo + (hi - lo) * u;
    }

  private:
    std::uint64_t state_;
};

}  // namespace gaitlab::detail
