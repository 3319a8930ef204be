// Tests for controllers/src/matsuoka.cpp: a half-centre oscillates near the frequency of
// Matsuoka's approximation, comes to rest when adaptation is too weak, and neighbour weights
// make a chain of them lock into a travelling wave.
#include "gaitlab/controllers/matsuoka.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gaitlab/error.h"
#include "rig.h"

using namespace gaitlab;
using namespace gaitlab::test;
using Catch::Matchers::Equals;
using gaitlab::controllers::Matsuoka;

namespace {

// records the upward zero crossings of each joint's output (interpolated between control
// steps) after `record_from` seconds
struct CrossingRig : Rig {
    CrossingRig(Controller& c, int n) : Rig(c, n), ups(joints.size()) {}
    void run(double seconds, double record_from = 1e9, double dt = 0.03) {
        const int angle = ctl.find_value("angle");
        std::vector<double> before = ctl.values(angle);
        run_each(seconds, dt, [&](double t) {
            const std::vector<double>& now = ctl.values(angle);
            for (size_t m = 0; m < joints.size(); ++m) {
                if (t >= record_from && before[m] < 0 && now[m] >= 0)
                    ups[m].push_back(t + dt * before[m] / (before[m] - now[m]));
            }
            before = now;
        });
    }
    double period(size_t m) const {
        return (ups[m].back() - ups[m].front()) / static_cast<double>(ups[m].size() - 1);
    }
    std::vector<std::vector<double>> ups;
};

// phase lead of joint m over joint m - 1 from their last upward zero crossings, (-180, 180] deg
double lead_deg(const CrossingRig& rig, size_t m) {
    const double dt = rig.ups[m - 1].back() - rig.ups[m].back();
    double d = std::fmod(360 * dt / rig.period(m), 360.0);
    if (d <= -180) d += 360;
    if (d > 180) d -= 360;
    return d;
}

}  // namespace

TEST_CASE("matsuoka declares its parameters, ranges, units and values") {
    const Matsuoka c;
    CHECK(c.name() == "matsuoka");
    const auto& p = c.def().params;
    REQUIRE(p.size() == 10);
    const char* names[] = {"gain",       "offset", "rise_time", "adaptation_time", "inhibition",
                           "adaptation", "tonic",  "ascending", "descending",      "seed"};
    const double defaults[] = {75, 0, 0.15, 0.9, 2, 2.5, 1, 0, 0, 0};
    const char* units[] = {"deg", "deg", "s", "s", "", "", "", "", "", ""};
    for (int i = 0; i < 10; ++i) {
        CAPTURE(i);
        CHECK(c.find_param(names[i]) == i);
        CHECK(p[i].default_value == defaults[i]);
        CHECK(p[i].unit == units[i]);
    }
    CHECK(c.find_value("u1") == Matsuoka::u1);
    CHECK(c.find_value("u2") == Matsuoka::u2);
    CHECK(c.find_value("angle") == Matsuoka::angle);
    Matsuoka d;
    REQUIRE_THROWS_WITH(d.set_param("rise_time", 0),
                        Equals("matsuoka.rise_time must be in [0.01, 10] s (got 0)"));
}

TEST_CASE("a matsuoka half-centre oscillates near the frequency its time constants give") {
    struct Case {
        double tau, big_t, a, b;
    };
    // (the approximation drifts for long adaptation times: 18% high at T / tau = 12, a = 2.5)
    const Case k =
        GENERATE(Case{0.15, 0.9, 2, 2.5}, Case{0.1, 0.5, 2, 2.5}, Case{0.2, 0.8, 1.5, 2});
    CAPTURE(k.tau, k.big_t, k.a, k.b);
    Matsuoka c;
    c.set_param("rise_time", k.tau);
    c.set_param("adaptation_time", k.big_t);
    c.set_param("inhibition", k.a);
    c.set_param("adaptation", k.b);
    CrossingRig rig(c, 1);
    rig.run(40, 20);
    REQUIRE(rig.ups[0].size() >= 5);
    // Matsuoka (2011): omega ~ (1/T) sqrt(((tau + T) b - tau a) / (tau a)), an approximation
    const double omega =
        std::sqrt(((k.tau + k.big_t) * k.b - k.tau * k.a) / (k.tau * k.a)) / k.big_t;
    const double f = 1 / rig.period(0);
    CAPTURE(f, omega / (2 * kTestPi));
    CHECK(f == Approx(omega / (2 * kTestPi)).epsilon(0.1));
    // a steady oscillation: successive periods agree
    const auto& ups = rig.ups[0];
    CHECK(ups[ups.size() - 1] - ups[ups.size() - 2] ==
          Approx(ups[ups.size() - 2] - ups[ups.size() - 3]).epsilon(1e-3));
}

TEST_CASE("a matsuoka half-centre stops, one neuron winning, when adaptation is too weak") {
    // for a > 1 + b mutual inhibition beats adaptation: neuron 1 or 2 stays on, y = c / (1 + b),
    // and holds the other at u = c - a y
    const double b = GENERATE(0.2, 0.5, 0.8);
    const double seed = GENERATE(0.0, 4.0);
    CAPTURE(b, seed);
    Matsuoka c;
    c.set_param("adaptation", b);
    c.set_param("seed", seed);
    CrossingRig rig(c, 1);
    rig.run(20);
    const double u1 = c.values(Matsuoka::u1)[0], u2 = c.values(Matsuoka::u2)[0];
    const double on = 1 / (1 + b), off = 1 - 2 * on;
    CHECK(std::max(u1, u2) == Approx(on).margin(1e-6));
    CHECK(std::min(u1, u2) == Approx(off).margin(1e-6));
    const double held = c.values(Matsuoka::angle)[0];
    CHECK(std::abs(held) == Approx(75 * on).margin(1e-4));
    rig.run(10, 0);
    CHECK(rig.ups[0].empty());
    CHECK(c.values(Matsuoka::angle)[0] == Approx(held).margin(1e-6));
}

TEST_CASE("a matsuoka half-centre decays to the symmetric rest when inhibition is too weak") {
    // for a < 1 + tau / T (here 1 + 1/6) the rest point u = v = y = c / (1 + a + b) is stable
    const double a = GENERATE(0.5, 1.0);
    CAPTURE(a);
    Matsuoka c;
    c.set_param("inhibition", a);
    c.set_param("seed", 4);
    CrossingRig rig(c, 1);
    rig.run(30);
    const double rest = 1 / (1 + a + 2.5);
    CHECK(c.values(Matsuoka::u1)[0] == Approx(rest).margin(1e-6));
    CHECK(c.values(Matsuoka::u2)[0] == Approx(rest).margin(1e-6));
    CHECK(std::abs(c.values(Matsuoka::angle)[0]) < 1e-4);
}

TEST_CASE("inhibitory neighbour weights lock a matsuoka chain into a travelling wave") {
    // an ascending weight (tail-side neighbour to this joint) and a descending one mirror
    // each other: the same lag, opposite signs
    const bool ascending = GENERATE(true, false);
    CAPTURE(ascending);
    Matsuoka c;
    c.set_param(ascending ? "ascending" : "descending", -0.5);
    CrossingRig rig(c, 6);
    rig.run(60, 40);
    std::vector<double> leads;
    for (size_t m = 1; m < 6; ++m) {
        CAPTURE(m);
        REQUIRE(rig.ups[m].size() >= 5);
        CHECK(rig.period(m) == Approx(rig.period(0)).epsilon(1e-3));
        leads.push_back(lead_deg(rig, m));
    }
    CAPTURE(leads);
    for (double lead : leads) {
        // a wave, neither standing (0 or 180) nor irregular
        CHECK(std::abs(lead) > 20);
        CHECK(std::abs(lead) < 170);
        CHECK(lead == Approx(leads[0]).margin(5));
        CHECK((ascending ? lead > 0 : lead < 0));
    }
}

TEST_CASE("matsuoka's trajectory hardly depends on the control period, and reset restarts it") {
    Matsuoka fine_c, coarse_c;
    CrossingRig fine(fine_c, 3), coarse(coarse_c, 3);
    fine.run(3, 1e9, 0.01);
    coarse.run(3, 1e9, 0.05);
    for (int k = 0; k < 3; ++k) {
        for (size_t m = 0; m < 3; ++m) {
            CAPTURE(k, m);
            CHECK(fine_c.values(k)[m] == Approx(coarse_c.values(k)[m]).margin(1e-6));
        }
    }
    const std::vector<double> first = coarse.targets;
    coarse_c.reset();
    CHECK(coarse_c.values(Matsuoka::u1) == std::vector<double>{0.1, 0.1, 0.1});
    coarse.run(3, 1e9, 0.05);
    CHECK(coarse.targets == first);
}
