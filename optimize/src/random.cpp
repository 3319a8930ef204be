#include "gaitlab/optimize/random.h"

#include <cmath>
#include <sstream>

#include "gaitlab/error.h"

namespace gaitlab::optimize {

double Random::uniform() {
    // 53 random bits make every double of [0, 1) with a spacing of 2^-53 equally likely
    return static_cast<double>(engine_() >> 11) * 0x1.0p-53;
}

std::uint64_t Random::below(std::uint64_t n) {
    if (n == 0) throw Error("Random::below: n must be positive");
    // reject the top partial block of 2^64 so that every residue is equally likely
    const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;
    for (;;) {
        const std::uint64_t r = engine_();
        if (r < limit) return r % n;
    }
}

double Random::normal() {
    for (;;) {
        const double a = 2.0 * uniform() - 1.0;
        const double b = 2.0 * uniform() - 1.0;
        const double s = a * a + b * b;
        if (s > 0.0 && s < 1.0) return a * std::sqrt(-2.0 * std::log(s) / s);
    }
}

std::string Random::state() const {
    std::ostringstream out;
    out << engine_;
    return out.str();
}

void Random::set_state(const std::string& text) {
    std::istringstream in(text);
    std::mt19937_64 engine;
    in >> engine;
    if (in.fail()) throw Error("not a random stream state (expected 313 whole numbers)");
    in >> std::ws;
    if (!in.eof()) throw Error("not a random stream state (text after its 313 numbers)");
    engine_ = engine;
}

}  // namespace gaitlab::optimize
