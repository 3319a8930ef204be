#include "gaitlab/controllers/hindmarsh_rose.h"

#include <cmath>
#include <cstdint>

#include "gaitlab/types.h"
#include "ode.h"

namespace gaitlab::controllers {

namespace {

constexpr double kRestX = -1.6;       // x_R
constexpr double kSpikeX = 1.0;       // a spike is an upward crossing of this x
constexpr double kSynapseE = -1.8;    // inhibitory reversal potential
constexpr double kSynapseX = -0.25;   // presynaptic threshold
constexpr double kSynapseSlope = 10;  // of the presynaptic sigmoid
// longest RK4 sub-step in model time: 0.1 gives the same spike counts and burst onsets as 0.01
// for a single neuron, and the same burst period within 1% for coupled ones, at 1/10 the cost
constexpr double kModelStep = 0.1;

}  // namespace

HindmarshRose::HindmarshRose()
    : Controller(ControllerDef{"hindmarsh_rose",
                               {{"amplitude", 40, 0, 90, "deg"},
                                {"offset", 0, -90, 90, "deg"},
                                {"current", 3, -5, 10, ""},
                                {"slow_rate", 0.005, 0.0001, 0.1, ""},
                                {"time_scale", 200, 1, 1000, "1/s"},
                                {"synapse", 0, 0, 5, ""},
                                {"burst_gap", 30, 1, 1000, ""},
                                {"smoothing", 0.1, 0.001, 10, "s"},
                                {"seed", 1, 0, 1e6, ""}},
                               {"x", "z", "bursting", "burst_spikes", "angle"}}),
      rk4_(std::make_unique<detail::Rk4>()) {}

HindmarshRose::~HindmarshRose() = default;

void HindmarshRose::on_bind() {
    const size_t n = static_cast<size_t>(joints());
    state_.assign(3 * n, 0.0);
    // identical neurons started alike stay in step; the seed spreads x over [-1.6, 0.4)
    const double sd = param(seed);
    for (size_t m = 0; m < n; ++m) {
        const double u = sd > 0 ? detail::seeded_unit(static_cast<std::uint64_t>(sd), m) : 0;
        const double x0 = kRestX + 2 * u;
        state_[3 * m] = x0;
        state_[3 * m + 1] = 1 - 5 * x0 * x0;
        state_[3 * m + 2] = 0;
    }
    since_spike_.assign(n, 1e9);
    count_.assign(n, 0);
    level_.assign(n, 0.0);
    for (size_t m = 0; m < n; ++m) {
        value(x)[m] = state_[3 * m];
        value(z)[m] = state_[3 * m + 2];
        value(angle)[m] = -param(amplitude) + param(offset);
    }
}

void HindmarshRose::step(ControlIO& io) {
    const int n = io.joints();
    const size_t un = static_cast<size_t>(n);
    const double current_i = param(current), r = param(slow_rate), g = param(synapse);
    const double gap = param(burst_gap);
    const double model_per_s = param(time_scale);
    const double tau = param(smoothing);
    // the presynaptic sigmoid of each neuron is computed once per evaluation, and not at all
    // without synapses (the default), where it was most of the cost
    sigmoid_.assign(un, 0.0);
    const auto deriv = [&](const std::vector<double>& s, std::vector<double>& ds) {
        if (g != 0) {
            for (size_t m = 0; m < un; ++m) {
                sigmoid_[m] = 1 / (1 + std::exp(-kSynapseSlope * (s[3 * m] - kSynapseX)));
            }
        }
        for (size_t m = 0; m < un; ++m) {
            const size_t k = 3 * m;
            const double xm = s[k], ym = s[k + 1], zm = s[k + 2];
            // fast threshold modulation: a neighbour inhibits while its x is high
            double syn = 0;
            if (g != 0) {
                const double neighbours =
                    (m > 0 ? sigmoid_[m - 1] : 0.0) + (m + 1 < un ? sigmoid_[m + 1] : 0.0);
                syn = -g * (xm - kSynapseE) * neighbours;
            }
            ds[k] = ym + 3 * xm * xm - xm * xm * xm - zm + current_i + syn;
            ds[k + 1] = 1 - 5 * xm * xm - ym;
            ds[k + 2] = r * (4 * (xm - kRestX) - zm);
        }
    };
    std::vector<double> prev(un);
    for (size_t m = 0; m < un; ++m)
        prev[m] = state_[3 * m];
    // spikes last about one model time unit: detect them and follow bursts on every sub-step
    // every sub-step has the same length, so the filter's decay is computed once
    double keep_h = -1, keep = 0;
    const auto after = [&](const std::vector<double>& s, double h) {
        if (h != keep_h) {
            keep_h = h;
            keep = std::exp(-h / model_per_s / tau);
        }
        for (size_t m = 0; m < un; ++m) {
            const double xm = s[3 * m];
            since_spike_[m] += h;
            if (prev[m] < kSpikeX && xm >= kSpikeX) {
                if (since_spike_[m] > gap) count_[m] = 0;  // the first spike of a burst
                ++count_[m];
                since_spike_[m] = 0;
            }
            prev[m] = xm;
            const bool on = since_spike_[m] <= gap;
            if (!on && count_[m] > 0) {
                value(burst_spikes)[m] = count_[m];
                count_[m] = 0;
            }
            level_[m] = (on ? 1.0 : 0.0) + (level_[m] - (on ? 1.0 : 0.0)) * keep;
            value(bursting)[m] = on ? 1 : 0;
        }
    };
    rk4_->integrate(state_, io.dt() * model_per_s, kModelStep, deriv, after);
    for (size_t m = 0; m < un; ++m) {
        value(x)[m] = state_[3 * m];
        value(z)[m] = state_[3 * m + 2];
        value(angle)[m] = param(amplitude) * (2 * level_[m] - 1) + param(offset);
        io.set_target(static_cast<int>(m), deg_to_rad(value(angle)[m]));
    }
}

// the integrator's scratch space is not state: every step overwrites it before reading
HindmarshRose::HindmarshRose(const HindmarshRose& other)
    : Controller(other),
      state_(other.state_),
      since_spike_(other.since_spike_),
      count_(other.count_),
      level_(other.level_),
      sigmoid_(other.sigmoid_),
      rk4_(std::make_unique<detail::Rk4>()) {}

std::unique_ptr<Controller> HindmarshRose::clone() const {
    return std::unique_ptr<Controller>(new HindmarshRose(*this));
}

}  // namespace gaitlab::controllers
