#include "gaitlab/controllers/hopf.h"

#include <cmath>

#include "gaitlab/types.h"
#include "ode.h"

namespace gaitlab::controllers {

Hopf::Hopf()
    : Controller(ControllerDef{"hopf",
                               {{"amplitude", 40, 0, 90, "deg"},
                                {"frequency", 0.5, 0, 5, "Hz"},
                                {"phase", 120, -180, 180, "deg"},
                                {"offset", 0, -90, 90, "deg"},
                                {"convergence", 5, 0, 100, "1/s"},
                                {"coupling", 5, 0, 100, "1/s"},
                                {"seed", 0, 0, 1e6, ""}},
                               {"x", "y", "angle"}}),
      rk4_(std::make_unique<detail::Rk4>()) {}

Hopf::~Hopf() = default;

void Hopf::on_bind() {
    const size_t n = static_cast<size_t>(joints());
    state_.assign(2 * n, 0.0);
    // start on the limit cycle at phase 0 (z = 1, output at the offset), or with phases and
    // radii (0.2 ... 1.8) spread from the seed; z = 0 would be the unstable rest point
    const double sd = param(seed);
    for (size_t m = 0; m < n; ++m) {
        const double th = detail::initial_phase(sd, static_cast<int>(m));
        const double r =
            sd > 0 ? 0.2 + 1.6 * detail::seeded_unit(static_cast<std::uint64_t>(sd), n + m) : 1.0;
        state_[m] = r * std::cos(th);
        state_[n + m] = r * std::sin(th);
    }
    publish();
}

void Hopf::step(ControlIO& io) {
    const int n = io.joints();
    const double omega = 2 * kPi * param(frequency);
    const double lag = deg_to_rad(param(phase));
    const double c = std::cos(lag), s = std::sin(lag);
    const double gamma = param(convergence);
    const double k = param(coupling);
    const auto deriv = [&](const std::vector<double>& z, std::vector<double>& dz) {
        const double* xs = z.data();
        const double* ys = xs + n;
        double* dx = dz.data();
        double* dy = dx + n;
        for (int m = 0; m < n; ++m) {
            const double xm = xs[m], ym = ys[m];
            const double g = gamma * (1 - (xm * xm + ym * ym));
            double cx = 0, cy = 0;
            // the tail-side neighbour rotated forward by the lag, the head-side one back by it
            if (m > 0) {
                cx += c * xs[m - 1] - s * ys[m - 1] - xm;
                cy += s * xs[m - 1] + c * ys[m - 1] - ym;
            }
            if (m + 1 < n) {
                cx += c * xs[m + 1] + s * ys[m + 1] - xm;
                cy += -s * xs[m + 1] + c * ys[m + 1] - ym;
            }
            dx[m] = g * xm - omega * ym + k * cx;
            dy[m] = g * ym + omega * xm + k * cy;
        }
    };
    rk4_->integrate(state_, io.dt(), deriv);
    publish();
    const std::vector<double>& out = value(angle);
    for (int m = 0; m < n; ++m)
        io.set_target(m, deg_to_rad(out[static_cast<size_t>(m)]));
}

void Hopf::publish() {
    const size_t n = static_cast<size_t>(joints());
    std::vector<double>& xs = value(x);
    std::vector<double>& ys = value(y);
    std::vector<double>& out = value(angle);
    for (size_t m = 0; m < n; ++m) {
        xs[m] = state_[m];
        ys[m] = state_[n + m];
        // y = r sin(theta): a sine like the sine generator's, starting at the offset
        out[m] = param(amplitude) * state_[n + m] + param(offset);
    }
}

// the integrator's scratch space is not state: every step overwrites it before reading
Hopf::Hopf(const Hopf& other)
    : Controller(other), state_(other.state_), rk4_(std::make_unique<detail::Rk4>()) {}

std::unique_ptr<Controller> Hopf::clone() const {
    return std::unique_ptr<Controller>(new Hopf(*this));
}

}  // namespace gaitlab::controllers
