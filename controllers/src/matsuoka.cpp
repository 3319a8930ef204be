#include "gaitlab/controllers/matsuoka.h"

#include <algorithm>
#include <cstdint>

#include "gaitlab/types.h"
#include "ode.h"

namespace gaitlab::controllers {

Matsuoka::Matsuoka()
    : Controller(ControllerDef{"matsuoka",
                               {{"gain", 75, 0, 1000, "deg"},
                                {"offset", 0, -90, 90, "deg"},
                                {"rise_time", 0.15, 0.01, 10, "s"},
                                {"adaptation_time", 0.9, 0.01, 10, "s"},
                                {"inhibition", 2, 0, 10, ""},
                                {"adaptation", 2.5, 0, 10, ""},
                                {"tonic", 1, 0, 10, ""},
                                {"ascending", 0, -5, 5, ""},
                                {"descending", 0, -5, 5, ""},
                                {"seed", 0, 0, 1e6, ""}},
                               {"u1", "u2", "angle"}}),
      rk4_(std::make_unique<detail::Rk4>()) {}

Matsuoka::~Matsuoka() = default;

void Matsuoka::on_bind() {
    const size_t n = static_cast<size_t>(joints());
    state_.assign(4 * n, 0.0);
    // two identical neurons started alike would stay alike forever: break the symmetry by
    // starting neuron 1 slightly excited, or both at levels in [0, 0.5) drawn from the seed
    const double sd = param(seed);
    for (size_t m = 0; m < n; ++m) {
        if (sd > 0) {
            const auto s = static_cast<std::uint64_t>(sd);
            state_[4 * m] = 0.5 * detail::seeded_unit(s, 2 * m);
            state_[4 * m + 1] = 0.5 * detail::seeded_unit(s, 2 * m + 1);
        } else {
            state_[4 * m] = 0.1;
        }
    }
    publish();
}

void Matsuoka::step(ControlIO& io) {
    const int n = io.joints();
    const double tau = param(rise_time), big_t = param(adaptation_time);
    const double a = param(inhibition), b = param(adaptation), c = param(tonic);
    const double w_asc = param(ascending), w_desc = param(descending);
    const auto deriv = [&](const std::vector<double>& s, std::vector<double>& ds) {
        const auto y = [&](int m, int i) {
            return std::max(0.0, s[static_cast<size_t>(4 * m + i)]);
        };
        for (int m = 0; m < n; ++m) {
            const size_t k = static_cast<size_t>(4 * m);
            for (int i = 0; i < 2; ++i) {
                // each neuron hears the same-side neuron of its neighbours: from the tail side
                // through the ascending weight, from the head side through the descending one
                double input = 0;
                if (m > 0) input += w_asc * y(m - 1, i);
                if (m + 1 < n) input += w_desc * y(m + 1, i);
                const size_t ui = k + static_cast<size_t>(i);
                const size_t vi = k + 2 + static_cast<size_t>(i);
                ds[ui] = (c - s[ui] - a * y(m, 1 - i) - b * s[vi] + input) / tau;
                ds[vi] = (y(m, i) - s[vi]) / big_t;
            }
        }
    };
    rk4_->integrate(state_, io.dt(), deriv);
    publish();
    const std::vector<double>& out = value(angle);
    for (int m = 0; m < n; ++m)
        io.set_target(m, deg_to_rad(out[static_cast<size_t>(m)]));
}

void Matsuoka::publish() {
    const size_t n = static_cast<size_t>(joints());
    std::vector<double>& a1 = value(u1);
    std::vector<double>& a2 = value(u2);
    std::vector<double>& out = value(angle);
    for (size_t m = 0; m < n; ++m) {
        a1[m] = state_[4 * m];
        a2[m] = state_[4 * m + 1];
        const double y = std::max(0.0, a1[m]) - std::max(0.0, a2[m]);
        out[m] = param(gain) * y + param(offset);
    }
}

// the integrator's scratch space is not state: every step overwrites it before reading
Matsuoka::Matsuoka(const Matsuoka& other)
    : Controller(other), state_(other.state_), rk4_(std::make_unique<detail::Rk4>()) {}

std::unique_ptr<Controller> Matsuoka::clone() const {
    return std::unique_ptr<Controller>(new Matsuoka(*this));
}

}  // namespace gaitlab::controllers
