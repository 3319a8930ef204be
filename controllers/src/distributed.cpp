#include "gaitlab/controllers/distributed.h"

#include <cmath>
#include <cstdint>

#include "gaitlab/types.h"
#include "ode.h"

namespace gaitlab::controllers {

Distributed::Distributed()
    : Controller(ControllerDef{"distributed",
                               {{"amplitude", 40, 0, 90, "deg"},
                                {"frequency", 0.5, 0, 5, "Hz"},
                                {"phase", 120, -180, 180, "deg"},
                                {"offset", 0, -90, 90, "deg"},
                                {"coupling", 5, 0, 100, "1/s"},
                                {"detuning", 0, 0, 20, "%"},
                                {"failed", 0, 0, 1000, ""},
                                {"seed", 0, 0, 1e6, ""}},
                               {"theta", "own_frequency", "angle"}}),
      rk4_(std::make_unique<detail::Rk4>()) {}

Distributed::~Distributed() = default;

void Distributed::on_bind() {
    const int n = joints();
    state_.assign(static_cast<size_t>(2 * n), 0.0);
    for (int m = 0; m < n; ++m)
        state_[static_cast<size_t>(m)] = detail::initial_phase(param(seed), m);
    update_clocks();
    publish();
}

void Distributed::step(ControlIO& io) {
    const int n = io.joints();
    const size_t un = static_cast<size_t>(n);
    const double omega = 2 * kPi * param(frequency);
    const double lag = deg_to_rad(param(phase));
    const double k = param(coupling);
    // joint numbers in parameters count from 1, as users see them
    const int dead = static_cast<int>(std::lround(param(failed))) - 1;
    update_clocks();  // parameters may have changed since the last step
    const std::vector<double>& f_own = value(own_frequency);
    // message exchange: each module sends its phase; until the next exchange its neighbours
    // advance what they heard at the nominal frequency
    for (size_t m = 0; m < un; ++m)
        state_[un + m] = state_[m];
    const auto deriv = [&](const std::vector<double>& x, std::vector<double>& dx) {
        const double* th = x.data();
        const double* heard = th + n;
        for (int m = 0; m < n; ++m) {
            dx[static_cast<size_t>(n + m)] = omega;
            if (m == dead) {
                dx[static_cast<size_t>(m)] = 0;
                continue;
            }
            double d = 2 * kPi * f_own[static_cast<size_t>(m)];
            // the nearest live module on each side; across a failed module the lag doubles
            for (int side : {-1, 1}) {
                int j = m + side;
                double hops = 1;
                if (j == dead) {
                    j += side;
                    hops = 2;
                }
                if (j < 0 || j >= n) continue;
                d += k * std::sin(heard[j] - th[m] + side * -hops * lag);
            }
            dx[static_cast<size_t>(m)] = d;
        }
    };
    rk4_->integrate(state_, io.dt(), deriv);
    for (size_t m = 0; m < un; ++m)
        state_[m] = detail::wrap_phase(state_[m]);
    publish();
    const std::vector<double>& out = value(angle);
    for (int m = 0; m < n; ++m)
        io.set_target(m, deg_to_rad(out[static_cast<size_t>(m)]));
}

void Distributed::update_clocks() {
    const size_t n = static_cast<size_t>(joints());
    const double sd = param(seed), f = param(frequency), spread = param(detuning) / 100;
    std::vector<double>& fo = value(own_frequency);
    for (size_t m = 0; m < n; ++m) {
        // each module's clock is off by up to +-detuning, fixed per module by the seed
        const double u = sd > 0 ? detail::seeded_unit(static_cast<std::uint64_t>(sd), n + m) : 0.5;
        fo[m] = f * (1 + spread * (2 * u - 1));
    }
}

void Distributed::publish() {
    const size_t n = static_cast<size_t>(joints());
    const int dead = static_cast<int>(std::lround(param(failed))) - 1;
    std::vector<double>& th = value(theta);
    std::vector<double>& out = value(angle);
    for (size_t m = 0; m < n; ++m) {
        th[m] = rad_to_deg(state_[m]);
        const bool alive = static_cast<int>(m) != dead;
        out[m] = (alive ? param(amplitude) * std::sin(state_[m]) : 0) + param(offset);
    }
}

// the integrator's scratch space is not state: every step overwrites it before reading
Distributed::Distributed(const Distributed& other)
    : Controller(other), state_(other.state_), rk4_(std::make_unique<detail::Rk4>()) {}

std::unique_ptr<Controller> Distributed::clone() const {
    return std::unique_ptr<Controller>(new Distributed(*this));
}

}  // namespace gaitlab::controllers
