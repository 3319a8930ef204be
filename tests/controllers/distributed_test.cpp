// Tests for controllers/src/distributed.cpp: neighbour-only phase oscillators lock to the
// commanded lags despite their own clocks, messages once per control step, and a failed module.
#include "gaitlab/controllers/distributed.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gaitlab/error.h"
#include "rig.h"

using namespace gaitlab;
using namespace gaitlab::test;
using Catch::Matchers::Equals;
using gaitlab::controllers::Distributed;

namespace {

// largest |theta_j - theta_i - hops * lag| over neighbouring live modules, degrees
double worst_lag_error(const Distributed& c, double lag, int dead = -1) {
    const auto& th = c.values(Distributed::theta);
    double worst = 0;
    int prev = -1;
    for (int m = 0; m < static_cast<int>(th.size()); ++m) {
        if (m == dead) continue;
        if (prev >= 0) {
            const double want = (m - prev) * lag;
            const double got = th[static_cast<size_t>(m)] - th[static_cast<size_t>(prev)];
            worst = std::max(worst, std::abs(angle_diff_deg(got, want)));
        }
        prev = m;
    }
    return worst;
}

}  // namespace

TEST_CASE("distributed declares its parameters, ranges, units and values") {
    const Distributed c;
    CHECK(c.name() == "distributed");
    const auto& p = c.def().params;
    REQUIRE(p.size() == 8);
    const char* names[] = {"amplitude", "frequency", "phase",  "offset",
                           "coupling",  "detuning",  "failed", "seed"};
    const double defaults[] = {40, 0.5, 120, 0, 5, 0, 0, 0};
    const char* units[] = {"deg", "Hz", "deg", "deg", "1/s", "%", "", ""};
    for (int i = 0; i < 8; ++i) {
        CAPTURE(i);
        CHECK(c.find_param(names[i]) == i);
        CHECK(p[i].default_value == defaults[i]);
        CHECK(p[i].unit == units[i]);
    }
    CHECK(c.find_value("theta") == Distributed::theta);
    CHECK(c.find_value("own_frequency") == Distributed::own_frequency);
    CHECK(c.find_value("angle") == Distributed::angle);
    Distributed d;
    REQUIRE_THROWS_WITH(d.set_param("detuning", 25),
                        Equals("distributed.detuning must be in [0, 20] % (got 25)"));
}

TEST_CASE("distributed modules lock to the commanded lags from spread phases") {
    const double lag = GENERATE(120.0, -90.0, 45.0);
    const double seed = GENERATE(0.0, 1.0, 7.0, 12345.0);
    const double dt = GENERATE(0.01, 0.03, 0.1);
    CAPTURE(lag, seed, dt);
    Distributed c;
    c.set_param("phase", lag);
    c.set_param("seed", seed);
    Rig rig(c, 8);
    rig.run(15, dt);
    CHECK(worst_lag_error(c, lag) < 1.0);
    for (size_t m = 0; m < 8; ++m) {
        const double th = c.values(Distributed::theta)[m] * kTestPi / 180;
        CHECK(c.values(Distributed::angle)[m] == Approx(40 * std::sin(th)).margin(1e-9));
    }
}

TEST_CASE("distributed modules on their own clocks still lock, to a common frequency") {
    const double seed = GENERATE(1.0, 2.0, 3.0);
    CAPTURE(seed);
    Distributed c;
    c.set_param("seed", seed);
    c.set_param("detuning", 2);
    Rig rig(c, 8);
    const auto& f = c.values(Distributed::own_frequency);
    const auto [lo, hi] = std::minmax_element(f.begin(), f.end());
    CHECK(*hi - *lo > 0.002);  // the clocks really differ
    CHECK(*lo >= 0.49);
    CHECK(*hi <= 0.51);
    rig.run(15);
    // locked despite the detuning: the lags hold still, close to the commanded ones
    const std::vector<double> before = c.values(Distributed::theta);
    const double err = worst_lag_error(c, 120);
    CHECK(err < 3.0);
    rig.run(3);
    CHECK(worst_lag_error(c, 120) == Approx(err).margin(0.01));
    // every module advanced by the same angle: one common frequency
    for (size_t m = 1; m < 8; ++m) {
        const double a0 = angle_diff_deg(c.values(Distributed::theta)[0], before[0]);
        const double am = angle_diff_deg(c.values(Distributed::theta)[m], before[m]);
        CHECK(am == Approx(a0).margin(0.01));
    }
}

TEST_CASE("the other distributed modules still lock when one fails") {
    const int failed = GENERATE(1, 4, 8);  // joint numbers count from 1
    CAPTURE(failed);
    Distributed c;
    c.set_param("seed", 11);
    c.set_param("failed", failed);
    c.set_param("offset", 5);
    Rig rig(c, 8);
    rig.run(15);
    // the modules either side of the failed one couple across it, at twice the lag
    CHECK(worst_lag_error(c, 120, failed - 1) < 1.0);
    const double held = c.values(Distributed::theta)[static_cast<size_t>(failed - 1)];
    rig.run(1);
    CHECK(c.values(Distributed::theta)[static_cast<size_t>(failed - 1)] == held);
    CHECK(c.values(Distributed::angle)[static_cast<size_t>(failed - 1)] == 5);
    CHECK(rig.targets[static_cast<size_t>(failed - 1)] == Approx(5 * kTestPi / 180));
}

TEST_CASE("distributed's reset restarts it bit for bit") {
    Distributed c;
    c.set_param("seed", 3);
    c.set_param("detuning", 5);
    Rig rig(c, 5);
    rig.run(2);
    const std::vector<double> first = rig.targets;
    c.reset();
    rig.run(2);
    CHECK(rig.targets == first);
}
