// Tests for controllers/src/sine.cpp: the sine generator against its formula, computed here
// independently, step by step through a ControlIO.
#include "gaitlab/controllers/sine.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "gaitlab/error.h"

using namespace gaitlab;
using Catch::Matchers::Equals;
using gaitlab::controllers::Sine;

namespace {

constexpr double kTestPi = 3.14159265358979323846;

// the sine never reads the joints; a reader that would notice if it did
class FakeReader final : public JointReader {
  public:
    mutable int reads = 0;
    double angle(int) const override {
        ++reads;
        return 0;
    }
    double velocity(int) const override {
        ++reads;
        return 0;
    }
    double torque(int) const override {
        ++reads;
        return 0;
    }
};

// theta_m(t) = A sin(2 pi f t + m dphi + phi0) + O, degrees, m 0-based
double expected_deg(double a, double f, double dphi, double phi0, double o, int m, double t) {
    const double r = kTestPi / 180;
    return a * std::sin(2 * kTestPi * f * t + m * dphi * r + phi0 * r) + o;
}

}  // namespace

TEST_CASE("the sine declares its parameters, ranges, units and values") {
    const Sine s;
    CHECK(s.name() == "sine");
    const auto& p = s.def().params;
    REQUIRE(p.size() == 5);
    const char* names[] = {"amplitude", "frequency", "phase", "phase0", "offset"};
    const double defaults[] = {40, 0.5, 120, 0, 0};
    const double mins[] = {0, 0, -180, -180, -90};
    const double maxs[] = {90, 5, 180, 180, 90};
    const char* units[] = {"deg", "Hz", "deg", "deg", "deg"};
    for (int i = 0; i < 5; ++i) {
        CAPTURE(i);
        CHECK(p[i].name == names[i]);
        CHECK(p[i].default_value == defaults[i]);
        CHECK(s.param(i) == defaults[i]);
        CHECK(p[i].min == mins[i]);
        CHECK(p[i].max == maxs[i]);
        CHECK(p[i].unit == units[i]);
    }
    CHECK(s.find_param("phase0") == Sine::phase0);
    CHECK(s.find_param("offset") == Sine::offset);
    CHECK(s.find_value("time") == Sine::time);
    CHECK(s.find_value("angle") == Sine::angle);
}

TEST_CASE("the sine rejects parameters out of range with the documented message") {
    Sine s;
    REQUIRE_THROWS_AS(s.set_param("amplitude", 120), SpecError);
    REQUIRE_THROWS_WITH(s.set_param("amplitude", 120),
                        Equals("sine.amplitude must be in [0, 90] deg (got 120)"));
    REQUIRE_THROWS_WITH(s.set_param("frequency", -0.5),
                        Equals("sine.frequency must be in [0, 5] Hz (got -0.5)"));
    REQUIRE_THROWS_WITH(s.set_param("phase", 200),
                        Equals("sine.phase must be in [-180, 180] deg (got 200)"));
    REQUIRE_THROWS_WITH(s.set_param("offset", -91),
                        Equals("sine.offset must be in [-90, 90] deg (got -91)"));
}

TEST_CASE("the sine follows its formula for every joint and step") {
    struct Case {
        double a, f, dphi, phi0, o;
    };
    const Case c = GENERATE(Case{40, 0.5, 120, 0, 0}, Case{25, 1.3, -90, 30, 10},
                            Case{90, 5, 180, -180, -90}, Case{0, 2, 45, 0, 17.5});
    CAPTURE(c.a, c.f, c.dphi, c.phi0, c.o);
    Sine s;
    s.set_param("amplitude", c.a);
    s.set_param("frequency", c.f);
    s.set_param("phase", c.dphi);
    s.set_param("phase0", c.phi0);
    s.set_param("offset", c.o);
    const int n = 5;
    s.bind(n);
    const std::vector<int> joints{9, 7, 5, 3, 1};  // a group's joints need not be in order
    const FakeReader reader;
    std::vector<double> targets(n, 0);
    const double dt = 0.03;
    for (int k = 1; k <= 40; ++k) {
        ControlIO io(dt, (k - 1) * dt, joints, reader, targets.data());
        s.step(io);
        // each joint's clock advanced by dt before use: after k steps it reads k * dt
        const double t = k * dt;
        for (int m = 0; m < n; ++m) {
            CAPTURE(k, m);
            const double deg = expected_deg(c.a, c.f, c.dphi, c.phi0, c.o, m, t);
            CHECK(targets[m] == Approx(deg * kTestPi / 180).margin(1e-12));
            CHECK(s.values(Sine::time)[m] == Approx(t).epsilon(1e-12));
            CHECK(s.values(Sine::angle)[m] == Approx(deg).margin(1e-10));
        }
    }
    CHECK(reader.reads == 0);
}

TEST_CASE("the sine's first step is at t = control_dt, and reset restarts its clocks") {
    Sine s;  // defaults: 40 deg, 0.5 Hz, 120 deg
    s.bind(3);
    const std::vector<int> joints{0, 1, 2};
    const FakeReader reader;
    std::vector<double> first(3), again(3);
    const double dt = 0.05;
    ControlIO io1(dt, 0, joints, reader, first.data());
    s.step(io1);
    CHECK(first[0] == Approx(40 * std::sin(2 * kTestPi * 0.5 * dt) * kTestPi / 180));
    CHECK(first[0] != 0);
    ControlIO io2(dt, dt, joints, reader, again.data());
    s.step(io2);
    CHECK(again != first);

    s.reset();
    CHECK(s.values(Sine::time) == std::vector<double>{0, 0, 0});
    CHECK(s.values(Sine::angle) == std::vector<double>{0, 0, 0});
    ControlIO io3(dt, 0, joints, reader, again.data());
    s.step(io3);
    CHECK(again == first);  // bit for bit
}

TEST_CASE("a parameter change takes effect at the next step, clocks continue") {
    Sine s;
    s.bind(2);
    const std::vector<int> joints{0, 1};
    const FakeReader reader;
    std::vector<double> targets(2);
    const double dt = 0.03;
    for (int k = 0; k < 10; ++k) {
        ControlIO io(dt, k * dt, joints, reader, targets.data());
        s.step(io);
    }
    s.set_param("amplitude", 10);
    s.set_param("offset", -5);
    ControlIO io(dt, 10 * dt, joints, reader, targets.data());
    s.step(io);
    const double t = 11 * dt;
    CHECK(s.values(Sine::time)[1] == Approx(t));
    CHECK(s.values(Sine::angle)[1] == Approx(expected_deg(10, 0.5, 120, 0, -5, 1, t)));
    CHECK(targets[1] == Approx(expected_deg(10, 0.5, 120, 0, -5, 1, t) * kTestPi / 180));
}

TEST_CASE("each joint keeps its own clock, using the dt of each step") {
    // with a varying control period the clock is the sum of the dts, not k * dt
    Sine s;
    s.set_param("phase", 0);
    s.bind(1);
    const std::vector<int> joints{0};
    const FakeReader reader;
    std::vector<double> targets(1);
    double t = 0;
    for (double dt : {0.01, 0.02, 0.04}) {
        ControlIO io(dt, t, joints, reader, targets.data());
        s.step(io);
        t += dt;
    }
    CHECK(s.values(Sine::time)[0] == Approx(0.07));
    CHECK(targets[0] == Approx(40 * std::sin(2 * kTestPi * 0.5 * 0.07) * kTestPi / 180));
}
