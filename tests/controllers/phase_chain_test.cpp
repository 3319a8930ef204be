// Tests for controllers/src/phase_chain.cpp: the chain of amplitude-controlled phase oscillators
// locks to the commanded lags, settles its amplitude without overshoot, runs at its frequency
// and, once locked, moves a robot like the equivalent sine gait.
#include "gaitlab/controllers/phase_chain.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "gaitlab/controllers/sine.h"
#include "gaitlab/error.h"
#include "gaitlab/simulation.h"
#include "rig.h"

using namespace gaitlab;
using namespace gaitlab::test;
using Catch::Matchers::Equals;
using gaitlab::controllers::PhaseChain;

namespace {

// largest |theta_m - theta_{m-1} - lag| over the chain, degrees
double worst_lag_error(const PhaseChain& c, double lag) {
    const auto& th = c.values(PhaseChain::theta);
    double worst = 0;
    for (size_t m = 1; m < th.size(); ++m)
        worst = std::max(worst, std::abs(angle_diff_deg(th[m] - th[m - 1], lag)));
    return worst;
}

}  // namespace

TEST_CASE("phase_chain declares its parameters, ranges, units and values") {
    const PhaseChain c;
    CHECK(c.name() == "phase_chain");
    check_declared_params(c, {{"amplitude", 40, 0, 90, "deg"},
                              {"frequency", 0.5, 0, 5, "Hz"},
                              {"phase", 120, -180, 180, "deg"},
                              {"offset", 0, -90, 90, "deg"},
                              {"coupling", 10, 0, 100, "1/s"},
                              {"gain", 20, 0, 200, "1/s"},
                              {"seed", 0, 0, 1e6, ""}});
    CHECK(c.find_value("theta") == PhaseChain::theta);
    CHECK(c.find_value("radius") == PhaseChain::radius);
    CHECK(c.find_value("angle") == PhaseChain::angle);
    PhaseChain d;
    REQUIRE_THROWS_WITH(d.set_param("coupling", -1),
                        Equals("phase_chain.coupling must be in [0, 100] 1/s (got -1)"));
}

TEST_CASE("phase_chain locks every neighbour lag to the commanded lag from spread phases") {
    const double lag = GENERATE(120.0, -90.0, 45.0, 0.0);
    const double seed = GENERATE(0.0, 1.0, 7.0, 12345.0);
    CAPTURE(lag, seed);
    PhaseChain c;
    c.set_param("phase", lag);
    c.set_param("seed", seed);
    Rig rig(c, 8);
    if (seed > 0) CHECK(worst_lag_error(c, lag) > 20);  // the seed really spreads the phases
    rig.run(8);
    CHECK(worst_lag_error(c, lag) < 1.0);
    rig.run(4);
    CHECK(worst_lag_error(c, lag) < 0.01);
    // locked: every output is r sin(theta) + offset on the common amplitude
    for (int m = 0; m < 8; ++m) {
        CAPTURE(m);
        const double th = c.values(PhaseChain::theta)[static_cast<size_t>(m)] * kTestPi / 180;
        CHECK(c.values(PhaseChain::angle)[static_cast<size_t>(m)] ==
              Approx(40 * std::sin(th)).margin(1e-6));
    }
}

TEST_CASE("phase_chain's amplitude rises to its setting critically damped, without overshoot") {
    const double target = GENERATE(40.0, 90.0, 5.0);
    CAPTURE(target);
    PhaseChain c;
    c.set_param("amplitude", target);
    Rig rig(c, 3);
    CHECK(c.values(PhaseChain::radius) == std::vector<double>{0, 0, 0});
    double max_r = 0;
    for (int k = 1; k <= 100; ++k) {  // 3 s
        rig.run(0.03);
        const double r = c.values(PhaseChain::radius)[1];
        max_r = std::max(max_r, r);
        // closed form from r = 0, dr/dt = 0: r(t) = R (1 - (1 + a t / 2) exp(-a t / 2)), a = 20
        const double t = rig.time;
        CAPTURE(t);
        CHECK(r == Approx(target * (1 - (1 + 10 * t) * std::exp(-10 * t))).margin(1e-7));
    }
    CHECK(max_r <= target * (1 + 1e-6));
    CHECK(c.values(PhaseChain::radius)[0] == Approx(target).margin(1e-6));
    // and down again when the amplitude drops, still without undershoot
    c.set_param("amplitude", target / 2);
    double min_r = target;
    for (int k = 0; k < 100; ++k) {
        rig.run(0.03);
        min_r = std::min(min_r, c.values(PhaseChain::radius)[2]);
    }
    CHECK(min_r >= target / 2 * (1 - 1e-6));
    CHECK(min_r == Approx(target / 2).margin(1e-6));
}

TEST_CASE("phase_chain runs at its frequency once locked") {
    const double f = GENERATE(0.5, 1.3, 3.0);
    CAPTURE(f);
    PhaseChain c;
    c.set_param("frequency", f);
    c.set_param("seed", 3);
    Rig rig(c, 8);
    rig.run(10);
    // upward zero crossings of joint 4's output, interpolated between control steps
    std::vector<double> ups;
    double prev = c.values(PhaseChain::angle)[4];
    for (int k = 0; k < 400; ++k) {
        const double t0 = rig.time;
        rig.run(0.03);
        const double now = c.values(PhaseChain::angle)[4];
        if (prev < 0 && now >= 0) ups.push_back(t0 + 0.03 * prev / (prev - now));
        prev = now;
    }
    REQUIRE(ups.size() >= 4);
    const double period = (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
    CHECK(period == Approx(1 / f).epsilon(0.002));
}

TEST_CASE("phase_chain's trajectory hardly depends on the control period") {
    PhaseChain fine_c, coarse_c;
    fine_c.set_param("seed", 5);
    coarse_c.set_param("seed", 5);
    Rig fine(fine_c, 6), coarse(coarse_c, 6);
    check_period_independent(fine, coarse, 3, 1e-8);
}

TEST_CASE("phase_chain's reset restarts it bit for bit, parameters kept") {
    PhaseChain c;
    c.set_param("seed", 9);
    c.set_param("frequency", 1);
    Rig rig(c, 4);
    rig.run(2);
    const std::vector<double> first = rig.targets;
    c.reset();
    CHECK(c.values(PhaseChain::radius) == std::vector<double>{0, 0, 0, 0});
    CHECK(c.param("frequency") == 1);
    rig.run(2);
    CHECK(rig.targets == first);
}

TEST_CASE("once locked, phase_chain moves a pitch-pitch robot like the equivalent sine") {
    const double lag = GENERATE(120.0, -120.0);
    CAPTURE(lag);
    auto sine = std::make_shared<controllers::Sine>();
    sine->set_param("phase", lag);
    auto cpg = std::make_shared<PhaseChain>();
    cpg->set_param("phase", lag);
    cpg->set_param("seed", 2);
    const Vec3 s = pitch_pitch_displacement(sine, 4, 8);
    const Vec3 p = pitch_pitch_displacement(cpg, 4, 8);
    CAPTURE(s.x, s.y, p.x, p.y);
    // a positive lag sends the wave head to tail: the robot goes tail first (-x)
    CHECK(std::abs(s.x) > 0.05);
    CHECK((lag > 0 ? s.x < 0 : s.x > 0));
    CHECK(p.x * s.x > 0);
    CHECK(p.x == Approx(s.x).epsilon(0.1));
    CHECK(std::abs(p.y) < 0.1 * std::abs(p.x));
}
