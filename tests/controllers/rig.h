// What the controller tests share: a rig that drives one controller alone, without physics,
// its joints still at zero; checks of a controller's declared parameters and of how little its
// trajectory depends on the control period; a robot it drives on the floor; angle helpers.
#pragma once

#include <catch2/catch.hpp>

#include <cmath>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "gaitlab/controller.h"
#include "gaitlab/simulation.h"

namespace gaitlab::test {

constexpr double kTestPi = 3.14159265358979323846;

// joints that never move
class StillJoints final : public JointReader {
  public:
    double angle(int) const override { return 0; }
    double velocity(int) const override { return 0; }
    double torque(int) const override { return 0; }
};

// drives a controller bound to n joints (indices 0..n-1) in control steps of dt seconds
struct Rig {
    Rig(Controller& c, int n) : ctl(c), joints(static_cast<size_t>(n)), targets(joints.size()) {
        for (int m = 0; m < n; ++m)
            joints[static_cast<size_t>(m)] = m;
        ctl.bind(n);
    }
    void run(double seconds, double dt = 0.03) {
        run_each(seconds, dt, [](double) {});
    }
    // runs `seconds`, calling each(t) after every step, t the time the step started at
    template <class Each>
    void run_each(double seconds, double dt, Each&& each) {
        const long steps = std::lround(seconds / dt);
        for (long k = 0; k < steps; ++k) {
            ControlIO io(dt, time, joints, reader, targets.data());
            ctl.step(io);
            each(time);
            time += dt;
        }
    }
    Controller& ctl;
    std::vector<int> joints;
    std::vector<double> targets;
    StillJoints reader;
    double time = 0;
};

// a parameter as a controller declares it
struct DeclaredParam {
    const char* name;
    double default_value, min, max;
    const char* unit;
};

// `c` declares `expected`, in that order, each found by its name
inline void check_declared_params(const Controller& c, const std::vector<DeclaredParam>& expected) {
    const auto& p = c.def().params;
    REQUIRE(p.size() == expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
        CAPTURE(i);
        CHECK(c.find_param(expected[i].name) == static_cast<int>(i));
        CHECK(p[i].default_value == expected[i].default_value);
        CHECK(p[i].min == expected[i].min);
        CHECK(p[i].max == expected[i].max);
        CHECK(p[i].unit == expected[i].unit);
    }
}

// runs two rigs, their controllers set up alike, for 3 s in control steps of 10 ms (`fine`)
// and 50 ms (`coarse`): the first `values` values agree on every joint within `margin`
inline void check_period_independent(Rig& fine, Rig& coarse, int values, double margin) {
    fine.run(3, 0.01);
    coarse.run(3, 0.05);
    for (int k = 0; k < values; ++k) {
        for (size_t m = 0; m < fine.joints.size(); ++m) {
            CAPTURE(k, m);
            CHECK(fine.ctl.values(k)[m] == Approx(coarse.ctl.values(k)[m]).margin(margin));
        }
    }
}

// displacement (m) of an 8-module pitch-pitch robot that `ctl` drives, all joints, on the floor
// between `settle` and `settle + span` seconds
inline Vec3 pitch_pitch_displacement(std::shared_ptr<Controller> ctl, double settle, double span) {
    ChainSpec chain;
    chain.modules = 8;
    PlacedRobot robot{make_chain(chain), {}, {}};
    robot.actuation.push_back({select_joints(robot.robot, "all"), std::move(ctl)});
    WorldSpec world;
    world.robots.push_back(robot);
    Simulation sim(world);
    sim.run(settle);
    const Vec3 start = sim.robot_displacement(0);
    sim.run(span);
    const Vec3 end = sim.robot_displacement(0);
    return Vec3{end.x - start.x, end.y - start.y, end.z - start.z};
}

// a - b wrapped into (-180, 180], degrees
inline double angle_diff_deg(double a, double b) {
    double d = std::fmod(a - b, 360.0);
    if (d <= -180) d += 360;
    if (d > 180) d -= 360;
    return d;
}

}  // namespace gaitlab::test
