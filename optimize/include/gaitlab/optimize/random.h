// The random numbers of the optimization methods: a stream defined by gaitlab, not by the
// standard library. std::mt19937_64's sequence is fixed by the C++ standard, but the std::
// distributions are not (libstdc++ and libc++ draw different normals from the same engine), so
// the distributions are written here: the same seed gives the same numbers with any compiler
// and standard library with IEEE doubles (sqrt is exact; log, in normal(), is the C library's:
// glibc gives the same results on every Debian machine).
#pragma once

#include <cstdint>
#include <random>
#include <string>

namespace gaitlab::optimize {

/// A seeded random stream: std::mt19937_64 with gaitlab's own distributions.
class Random {
  public:
    /// A stream that starts from `seed` (std::mt19937_64's seeding).
    explicit Random(std::uint64_t seed) : engine_(seed) {}

    /// The engine's next 64 bits.
    std::uint64_t bits() { return engine_(); }

    /// A uniform number in [0, 1): the top 53 bits of one draw, times 2^-53.
    double uniform();

    /// A uniform whole number in [0, n), n > 0, without modulo bias (rejection sampling).
    std::uint64_t below(std::uint64_t n);

    /// A standard normal number (mean 0, deviation 1): Marsaglia's polar method, one value per
    /// accepted pair (the second is dropped, so the stream's state is the engine's alone).
    double normal();

    /// The engine's state as text (the standard's textual form of mt19937_64: 313 numbers).
    std::string state() const;

    /// Restores a state() text; throws Error when it is not one.
    void set_state(const std::string& text);

  private:
    std::mt19937_64 engine_;
};

}  // namespace gaitlab::optimize
