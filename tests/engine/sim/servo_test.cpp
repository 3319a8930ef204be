// Tests for engine/include/gaitlab/servo.h: the servo law, and the servo as the physics applies it
// (speed and torque limits, joint range), measured through the public Simulation API.
#include "gaitlab/servo.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "engine/sim_support.h"
#include "gaitlab/types.h"

using namespace gaitlab;

namespace {

// largest |speed|, |torque| and angle excursion of every joint of robot 0 over a run
struct Extremes {
    double speed = 0;
    double torque = 0;
    double max_angle = -1e9;
    double min_angle = 1e9;
};

Extremes watch(Simulation& sim, double seconds) {
    Extremes e;
    const int n = static_cast<int>(sim.world().robots[0].robot.joints.size());
    const int id = sim.add_observer([&e, n](const Simulation& s) {
        for (int j = 0; j < n; ++j) {
            const JointState js = s.joint(0, j);
            e.speed = std::max(e.speed, std::abs(js.velocity));
            e.torque = std::max(e.torque, std::abs(js.torque));
            e.max_angle = std::max(e.max_angle, js.angle);
            e.min_angle = std::min(e.min_angle, js.angle);
        }
    });
    sim.run(seconds);
    sim.remove_observer(id);
    return e;
}

// the solver meets the motor's velocity constraint only up to its iteration count and the other
// rows' position corrections (which add a little angular velocity), so measured speeds may pass
// the command by a small amount; 2% of 4.5 rad/s is 0.09 rad/s, far below a real violation
constexpr double kSpeedTolerance = 1.02;
// the torque is rebuilt from the constraint's feedback, which the solver computes with the poses
// before the step, projected on the joint axis after the step; the axis turns by up to
// max_speed * dt = 0.0045 rad in a step, mixing that fraction of the (larger) off-axis constraint
// torques into the reading: 1% of max_torque covers it
constexpr double kTorqueTolerance = 1.01;

}  // namespace

TEST_CASE("servo_command is proportional to the error") {
    const ServoDef s = default_servo_def();
    CHECK(s.kp == 8.3);
    CHECK(s.max_speed == 4.5);
    CHECK(s.max_torque == 0.4);
    CHECK(servo_command(s, 0, 0) == 0);
    CHECK(servo_command(s, 0.1, 0) == Approx(0.83));
    CHECK(servo_command(s, 0, 0.1) == Approx(-0.83));
    CHECK(servo_command(s, 0.3, 0.2) == Approx(0.83));
    CHECK(servo_command(s, -0.25, 0.25) == Approx(-4.15));
}

TEST_CASE("servo_command is clamped to +-max_speed") {
    const ServoDef s = default_servo_def();
    CHECK(servo_command(s, 1, 0) == 4.5);
    CHECK(servo_command(s, -1, 0) == -4.5);
    CHECK(servo_command(s, kPi / 2, -kPi / 2) == 4.5);
    // the error at which the clamp starts: 4.5 / 8.3 rad
    CHECK(servo_command(s, 4.5 / 8.3 - 1e-3, 0) < 4.5);
    ServoDef fast = s;
    fast.max_speed = 10;
    fast.kp = 2;
    CHECK(servo_command(fast, 3, 0) == 6);
    CHECK(servo_command(fast, 6, 0) == 10);
}

TEST_CASE("a servo tracks a reachable target") {
    // a step to 20 deg on a floating 2-module chain: first at full speed, then proportional
    Simulation sim(test::chain_world(2, Connection::pitch_pitch, false));
    test::drive(sim, "all", test::sine(0, 0, 0, 0, 20));
    sim.run(1.0);
    for (int j = 0; j < 2; ++j) {
        CAPTURE(j);
        CHECK(sim.joint(0, j).target == Approx(deg_to_rad(20)));
        CHECK(sim.joint(0, j).angle == Approx(deg_to_rad(20)).margin(deg_to_rad(0.5)));
        CHECK(std::abs(sim.joint(0, j).velocity) < 0.01);
    }
}

TEST_CASE("a fast target never makes a floating joint exceed its speed or torque") {
    // a 2 Hz, 60 deg sine asks for up to 13 rad/s; the servo must saturate at 4.5 rad/s
    const ServoDef s = default_servo_def();
    Simulation sim(test::chain_world(2, Connection::pitch_yaw, false));
    test::drive(sim, "all", test::sine(60, 2, 90));
    const Extremes e = watch(sim, 2.0);
    CAPTURE(e.speed, e.torque);
    CHECK(e.speed > 0.9 * s.max_speed);  // it does run into the limit
    CHECK(e.speed <= s.max_speed * kSpeedTolerance);
    CHECK(e.torque > 0);
    CHECK(e.torque <= s.max_torque * kTorqueTolerance);
}

TEST_CASE("servo torques stay within max_torque on the floor") {
    // a fast gait of an 8-module chain: lifting the chain needs the full torque of some servos
    const ServoDef s = default_servo_def();
    Simulation sim(test::chain_world(8, Connection::pitch_pitch));
    test::drive(sim, "all", test::sine(60, 2, 120));
    const Extremes e = watch(sim, 2.0);
    CAPTURE(e.torque);
    CHECK(e.torque > 0.9 * s.max_torque);
    CHECK(e.torque <= s.max_torque * kTorqueTolerance);
}

// on the floor the sequential-impulse solver handles the contact rows after the joint motors in
// each iteration, so joints can end a step slightly faster than commanded while the motor is far
// from its torque limit; with the default 20 iterations this stays within kSpeedTolerance except
// for the jolt when a gait starts from rest with every servo at full speed at once (measured
// 4.75 rad/s, +5.6%): allow 7% there. A joint whose servo runs flat out while its body rolls
// over the floor ends up to 3.2% fast (2-module chain, 60 deg at 2 Hz): allow 4% on the floor.
// (Gaits that ask far more than the servos can do, e.g. 40 deg at 2 Hz on 8 modules, still reach
// +11%: docs/conventions.md says so.)
constexpr double kStartTolerance = 1.07;
constexpr double kFloorSpeedTolerance = 1.04;

TEST_CASE("a fast target never makes a joint on the floor exceed its speed") {
    const ServoDef s = default_servo_def();
    Simulation sim(test::chain_world(2, Connection::pitch_pitch));
    test::drive(sim, "all", test::sine(60, 2, 120));
    const Extremes e = watch(sim, 2.0);
    CAPTURE(e.speed, e.torque);
    CHECK(e.speed > 0.9 * s.max_speed);
    CHECK(e.torque < 0.5 * s.max_torque);  // light load: no back-driving
    CHECK(e.speed <= s.max_speed * kFloorSpeedTolerance);
}

TEST_CASE("in the standard gait joints keep to the servo speed once it has started") {
    const ServoDef s = default_servo_def();
    Simulation sim(test::chain_world(8, Connection::pitch_pitch));
    test::drive_pitch_pitch_gait(sim, 120);
    const Extremes start = watch(sim, 0.1);
    const Extremes steady = watch(sim, 5.0);
    CAPTURE(start.speed, steady.speed, steady.torque);
    CHECK(start.speed > 0.9 * s.max_speed);  // every servo starts flat out
    CHECK(start.speed <= s.max_speed * kStartTolerance);
    CHECK(steady.speed <= s.max_speed * kSpeedTolerance);
    CHECK(steady.torque <= s.max_torque * kTorqueTolerance);
}

TEST_CASE("a target beyond the range is clamped and the joint stays within +-90 deg") {
    // offset 60 + amplitude 80 asks for -20 .. 140 deg; offset -60 for -140 .. 20 deg
    const double sign = GENERATE(1.0, -1.0);
    CAPTURE(sign);
    Simulation sim(test::chain_world(2, Connection::pitch_yaw, false));
    test::drive(sim, "all", test::sine(80, 0.5, 0, 0, 60 * sign));
    bool clamped = false;
    sim.add_observer([&clamped](const Simulation& st) {
        for (int j = 0; j < 2; ++j) {
            const double t = st.joint(0, j).target;
            CHECK(std::abs(t) <= kPi / 2);
            if (std::abs(t) == kPi / 2) clamped = true;
        }
    });
    const Extremes e = watch(sim, 2.0);
    CHECK(clamped);
    // the range stop is a soft constraint: allow 1 deg of overshoot
    const double limit = deg_to_rad(90) + deg_to_rad(1);
    CHECK(e.max_angle <= limit);
    CHECK(e.min_angle >= -limit);
    // it does get there
    if (sign > 0) CHECK(e.max_angle > deg_to_rad(88));
    if (sign < 0) CHECK(e.min_angle < -deg_to_rad(88));
}

TEST_CASE("the largest servo values a module takes run without overflow at the default dt") {
    // kp, max_speed and max_torque at their bounds on a light, a heavy and a long chain: the
    // joints whip around (bang-bang at 1000 rad/s), but every state stays finite
    struct Case {
        double mass, length;
        int modules;
    };
    const Case c = GENERATE(Case{0.05, 0.072, 3}, Case{1e6, 100, 3}, Case{0.001, 0.01, 3},
                            Case{0.05, 0.072, 8});
    ModuleDef m;
    m.name = "extreme";
    m.mass = c.mass;
    m.length = c.length;
    m.width = m.height = 0.7 * c.length;
    m.min_angle = -kPi;
    m.max_angle = kPi;
    m.servo = {kMaxServoKp, kMaxServoSpeed, kMaxServoTorque};
    ChainSpec spec;
    spec.name = "r";
    spec.modules = c.modules;
    spec.connection = Connection::pitch_yaw;
    spec.module = m;
    CAPTURE(c.mass, c.length, c.modules);
    Simulation sim(test::world_of(make_chain(spec)));
    test::drive(sim, "all", test::sine(90, 1, 90));
    REQUIRE_NOTHROW(sim.run(1.0));
    for (int j = 0; j < c.modules; ++j) {
        CHECK(std::isfinite(sim.joint(0, j).angle));
        CHECK(std::abs(sim.joint(0, j).velocity) <= kMaxServoSpeed * kStartTolerance);
    }
}
