// Tests for controllers/src/hopf.cpp: a Hopf oscillator converges to its unit limit cycle at its
// frequency, a chain of them locks to the commanded lags, and the locked chain walks a robot.
#include "gaitlab/controllers/hopf.h"

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
using gaitlab::controllers::Hopf;

namespace {

double radius(const Hopf& h, size_t m) {
    return std::hypot(h.values(Hopf::x)[m], h.values(Hopf::y)[m]);
}

// phase of oscillator m, degrees
double phase_deg(const Hopf& h, size_t m) {
    return std::atan2(h.values(Hopf::y)[m], h.values(Hopf::x)[m]) * 180 / kTestPi;
}

}  // namespace

TEST_CASE("hopf declares its parameters, ranges, units and values") {
    const Hopf h;
    CHECK(h.name() == "hopf");
    check_declared_params(h, {{"amplitude", 40, 0, 90, "deg"},
                              {"frequency", 0.5, 0, 5, "Hz"},
                              {"phase", 120, -180, 180, "deg"},
                              {"offset", 0, -90, 90, "deg"},
                              {"convergence", 5, 0, 100, "1/s"},
                              {"coupling", 5, 0, 100, "1/s"},
                              {"seed", 0, 0, 1e6, ""}});
    CHECK(h.find_value("x") == Hopf::x);
    CHECK(h.find_value("y") == Hopf::y);
    CHECK(h.find_value("angle") == Hopf::angle);
    Hopf g;
    REQUIRE_THROWS_WITH(g.set_param("convergence", 101),
                        Equals("hopf.convergence must be in [0, 100] 1/s (got 101)"));
}

TEST_CASE("a single hopf oscillator converges to radius 1 and turns at its frequency") {
    const double seed = GENERATE(1.0, 2.0, 3.0, 4.0);
    const double f = GENERATE(0.5, 2.0);
    CAPTURE(seed, f);
    Hopf h;
    h.set_param("seed", seed);
    h.set_param("frequency", f);
    Rig rig(h, 1);
    const double r0 = radius(h, 0), th0 = phase_deg(h, 0);
    CHECK(std::abs(r0 - 1) > 0.01);  // the seed really starts it off the cycle
    const double gamma = 5;
    for (int k = 0; k < 100; ++k) {  // 3 s
        rig.run(0.03);
        const double t = rig.time;
        CAPTURE(t);
        // r^2 is logistic: r^2(t) = 1 / (1 + (1 / r0^2 - 1) exp(-2 gamma t))
        const double r2 = 1 / (1 + (1 / (r0 * r0) - 1) * std::exp(-2 * gamma * t));
        CHECK(radius(h, 0) == Approx(std::sqrt(r2)).margin(1e-8));
        // the phase advances at 2 pi f whatever the radius (exactly in the model; RK4 with 5 ms
        // sub-steps drifts by about 1e-4 deg in this 3 s run at 2 Hz)
        CHECK(angle_diff_deg(phase_deg(h, 0), th0 + 360 * f * t) == Approx(0).margin(1e-3));
    }
    CHECK(radius(h, 0) == Approx(1).margin(1e-9));
    CHECK(h.values(Hopf::angle)[0] == Approx(40 * h.values(Hopf::y)[0]));
}

TEST_CASE("a hopf chain locks to the commanded lags on the unit circle") {
    const double lag = GENERATE(120.0, -90.0, 45.0);
    const double seed = GENERATE(0.0, 1.0, 7.0, 12345.0);
    CAPTURE(lag, seed);
    Hopf h;
    h.set_param("phase", lag);
    h.set_param("seed", seed);
    Rig rig(h, 8);
    rig.run(15);
    for (size_t m = 0; m < 8; ++m) {
        CAPTURE(m);
        CHECK(radius(h, m) == Approx(1).margin(1e-3));
        if (m > 0) {
            CHECK(angle_diff_deg(phase_deg(h, m) - phase_deg(h, m - 1), lag) ==
                  Approx(0).margin(1.0));
        }
    }
}

TEST_CASE("hopf's trajectory hardly depends on the control period, and reset restarts it") {
    Hopf fine_h, coarse_h;
    fine_h.set_param("seed", 5);
    coarse_h.set_param("seed", 5);
    Rig fine(fine_h, 6), coarse(coarse_h, 6);
    check_period_independent(fine, coarse, 3, 1e-8);
    const std::vector<double> first = coarse.targets;
    coarse_h.reset();
    coarse.run(3, 0.05);
    CHECK(coarse.targets == first);
}

TEST_CASE("once locked, hopf moves a pitch-pitch robot like the equivalent sine") {
    // from phase 0 everywhere the default chain locks within 10 s
    const double s = pitch_pitch_displacement(std::make_shared<controllers::Sine>(), 10, 8).x;
    const double p = pitch_pitch_displacement(std::make_shared<Hopf>(), 10, 8).x;
    CAPTURE(s, p);
    CHECK(s < -0.05);  // a positive lag: tail first
    CHECK(p == Approx(s).epsilon(0.1));
}
