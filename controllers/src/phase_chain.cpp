#include "gaitlab/controllers/phase_chain.h"

#include <cmath>

#include "gaitlab/types.h"
#include "ode.h"

namespace gaitlab::controllers {

PhaseChain::PhaseChain()
    : Controller(ControllerDef{"phase_chain",
                               {{"amplitude", 40, 0, 90, "deg"},
                                {"frequency", 0.5, 0, 5, "Hz"},
                                {"phase", 120, -180, 180, "deg"},
                                {"offset", 0, -90, 90, "deg"},
                                {"coupling", 10, 0, 100, "1/s"},
                                {"gain", 20, 0, 200, "1/s"},
                                {"seed", 0, 0, 1e6, ""}},
                               {"theta", "radius", "angle"}}),
      rk4_(std::make_unique<detail::Rk4>()) {}

PhaseChain::~PhaseChain() = default;

void PhaseChain::on_bind() {
    const int n = joints();
    state_.assign(static_cast<size_t>(3 * n), 0.0);
    // amplitudes start at rest (r = 0, dr/dt = 0) so the output starts at the offset; phases
    // start at 0, or spread from the seed
    for (int m = 0; m < n; ++m)
        state_[static_cast<size_t>(m)] = detail::initial_phase(param(seed), m);
    publish();
}

void PhaseChain::step(ControlIO& io) {
    const int n = io.joints();
    const double omega = 2 * kPi * param(frequency);
    const double lag = deg_to_rad(param(phase));
    const double w = param(coupling);
    const double a = param(gain);
    const double big_r = deg_to_rad(param(amplitude));
    const auto deriv = [&](const std::vector<double>& x, std::vector<double>& dx) {
        const double* th = x.data();
        const double* r = th + n;
        const double* v = r + n;
        double* dth = dx.data();
        double* dr = dth + n;
        double* dv = dr + n;
        for (int m = 0; m < n; ++m) {
            double d = omega;
            // the tail-side neighbour should trail by `lag`, the head-side one lead by it
            if (m > 0) d += w * r[m - 1] * std::sin(th[m - 1] - th[m] + lag);
            if (m + 1 < n) d += w * r[m + 1] * std::sin(th[m + 1] - th[m] - lag);
            dth[m] = d;
            dr[m] = v[m];
            dv[m] = a * (a / 4 * (big_r - r[m]) - v[m]);
        }
    };
    rk4_->integrate(state_, io.dt(), deriv);
    // phases only enter through differences and sines: wrapping keeps them precise in long runs
    for (int m = 0; m < n; ++m)
        state_[static_cast<size_t>(m)] = detail::wrap_phase(state_[static_cast<size_t>(m)]);
    publish();
    const std::vector<double>& out = value(angle);
    for (int m = 0; m < n; ++m)
        io.set_target(m, deg_to_rad(out[static_cast<size_t>(m)]));
}

void PhaseChain::publish() {
    const size_t n = static_cast<size_t>(joints());
    std::vector<double>& th = value(theta);
    std::vector<double>& r = value(radius);
    std::vector<double>& out = value(angle);
    for (size_t m = 0; m < n; ++m) {
        th[m] = rad_to_deg(state_[m]);
        r[m] = rad_to_deg(state_[n + m]);
        out[m] = rad_to_deg(state_[n + m] * std::sin(state_[m])) + param(offset);
    }
}

// the integrator's scratch space is not state: every step overwrites it before reading
PhaseChain::PhaseChain(const PhaseChain& other)
    : Controller(other), state_(other.state_), rk4_(std::make_unique<detail::Rk4>()) {}

std::unique_ptr<Controller> PhaseChain::clone() const {
    return std::unique_ptr<Controller>(new PhaseChain(*this));
}

}  // namespace gaitlab::controllers
