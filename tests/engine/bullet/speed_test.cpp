// Issue 14, point 2, as the issue measures it: a gait's per-cycle speed (the mean length of each
// cycle's displacement) converges with the time step, where the direction a long pitch-yaw chain
// ends up travelling, solved without Newton steps, does not converge at all: it is chaotic, a
// billionth of a degree turns it (docs/performance.md, section 12, "Per-cycle speed"); with the
// Newton steps such a chain gets by default it is much less so ("Upright or on its side").
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <memory>

#include "engine/sim_support.h"
#include "gaitlab/types.h"

using namespace gaitlab;

namespace {

struct Gait {
    double speed = 0;  // m per cycle, the mean of each cycle's displacement length
    Vec3 travel;       // m per cycle, the whole displacement over the cycles
};

// the benchmark's pitch-yaw wave (pitch 40 deg, yaw 20 deg, 120 deg between neighbours, 0.5 Hz)
// on a chain of `modules`, the yaw sine moved by `offset` degrees: `settle` s to settle,
// then 10 cycles, with the engine's solver, floor and newton_steps (automatic: 8 from 13
// modules on) unless `newton` says
Gait py_wave(int modules, double friction, double dt, double offset, double settle = 2,
             int newton = kAutomaticNewtonSteps) {
    WorldSpec w = test::chain_world(modules, Connection::pitch_yaw);
    w.floor.friction = friction;
    SimulationOptions o = test::options_at(dt, 20, SimulationOptions{}.solver);
    o.newton_steps = newton;
    Simulation sim(w, o);
    test::drive(sim, "pitch", test::sine(40, 0.5, 120));
    test::drive(sim, "yaw", test::sine(20, 0.5, 120, 0, offset));
    sim.run(settle);
    const Vec3 start = sim.robot_position(0);
    Vec3 last = start;
    Gait g;
    constexpr int kCycles = 10;
    for (int c = 0; c < kCycles; ++c) {
        sim.run(2);
        const Vec3 p = sim.robot_position(0);
        g.speed += std::hypot(p.x - last.x, p.y - last.y) / kCycles;
        last = p;
    }
    g.travel = (last - start) * (1.0 / kCycles);
    return g;
}

double heading_deg(const Vec3& v) {
    return rad_to_deg(std::atan2(v.y, v.x));
}

}  // namespace

TEST_CASE(
    "a long pitch-yaw chain's heading turns with a nudge of 1e-9 deg, and its per-cycle speed "
    "does not, the less with Newton steps") {
    // 32 modules, friction 0.3, 10 cycles after the 20 s issue 14 settles its gaits, a yaw offset
    // of +-1e-9 deg. Without Newton steps it turns the path by degrees (8.7 measured) while the
    // speed stays within 8 % (79.1, 79.1 and 83.5 mm per cycle); with the 8 a 32-module chain
    // gets by default, by 1.3 deg, the speed within 1 % (with 4 Newton steps 0.04 deg: less
    // converged, their step damped the chain's stick-slip; at the reference, dt 0.25 ms and 80
    // iterations, 4 steps turn it 0.02 deg and 80.75 mm per cycle every time)
    // (the Newton half nudges one way only: its runs cost 3x as much, and -1e-9 deg turned it
    // 0.6 deg where +1e-9 turned it 1.3, the speed the same both ways to 0.01 mm)
    const auto nudged_turn = [](int newton, double speed_tolerance,
                                std::initializer_list<double> nudges) {
        const Gait base = py_wave(32, 0.3, 0.001, 0, 20, newton);
        CAPTURE(newton, base.speed, base.travel.x, base.travel.y);
        CHECK(base.speed > 0.05);  // it travels: about 8 cm per cycle
        double turned = 0;
        for (const double nudge : nudges) {
            const Gait nudged = py_wave(32, 0.3, 0.001, nudge, 20, newton);
            CAPTURE(nudge, nudged.speed, nudged.travel.x, nudged.travel.y);
            CHECK(std::abs(nudged.speed - base.speed) < speed_tolerance * base.speed);
            turned =
                std::max(turned, std::abs(heading_deg(nudged.travel) - heading_deg(base.travel)));
        }
        return turned;
    };
    CHECK(nudged_turn(0, 0.08, {1e-9, -1e-9}) > 3);
    CHECK(nudged_turn(kAutomaticNewtonSteps, 0.01, {1e-9}) < 3);
}

namespace {

// the bodies' mean tilt, deg: the angle of each body's z axis from the world's (0 upright, 90 on
// their side), as bench/lua/posture.lua measures it
double tilt_deg(const Simulation& sim, int bodies) {
    double sum = 0;
    for (int b = 0; b < bodies; ++b) {
        const Quat q = sim.body(0, b).pose.orientation;
        sum += rad_to_deg(std::acos(std::clamp(1 - 2 * (q.x * q.x + q.y * q.y), -1.0, 1.0)));
    }
    return sum / bodies;
}

}  // namespace

TEST_CASE("the 32-module wave settled upright stays upright at 4x the iterations") {
    // friction 1.0, 20 s at the defaults (upright: the bodies' mean tilt about 22 deg), then 20 s
    // more from that state at 80 iterations, as issue 14's "4x it" column (Simulation::clone at
    // other settings). With the 8 Newton steps such a chain gets it holds (65.2 mm per cycle);
    // with 4, the default until 2026-11-30, it tipped onto its side within the 20 s (mean tilt
    // 62 deg, 80.3 mm per cycle; after 40 s at the defaults the same, and so at 60 and 70
    // iterations, though not at 20, 40 or 90-320: docs/performance.md, section 12, "8 Newton
    // steps")
    WorldSpec w = test::chain_world(32, Connection::pitch_yaw);
    w.floor.friction = 1.0;
    Simulation sim(w, test::options_at(0.001, 20, SimulationOptions{}.solver));
    test::drive(sim, "pitch", test::sine(40, 0.5, 120));
    test::drive(sim, "yaw", test::sine(20, 0.5, 120));
    sim.run(20);
    REQUIRE(sim.options().newton_steps == kLongChainNewtonSteps);
    REQUIRE(tilt_deg(sim, 32) < 45);
    SimulationOptions more = sim.options();
    more.solver_iterations = 80;
    const std::unique_ptr<Simulation> copy = sim.clone(more);
    double worst = 0;
    for (int s = 0; s < 20; ++s) {
        copy->run(1);
        worst = std::max(worst, tilt_deg(*copy, 32));
    }
    CHECK(worst < 45);  // on its side: 60-80
}

TEST_CASE("a 16-module pitch-yaw wave's per-cycle speed is within 3 % at dt/4") {
    // friction 1.0, with the engine's solver, floor and the Newton steps such a chain gets: 65.3
    // and 65.2 mm per cycle with 4 (issue 14's bar; 65.6 and 65.2 without the steps)
    const Gait base = py_wave(16, 1.0, 0.001, 0);
    const Gait fine = py_wave(16, 1.0, 0.00025, 0);
    CAPTURE(base.speed, fine.speed);
    CHECK(base.speed > 0.05);
    CHECK(std::abs(fine.speed - base.speed) < 0.03 * fine.speed);
}

namespace {

// the smallest pitch-yaw robot with a wave (CLAWAR 2005's PYP: 3 modules, two pitch joints and
// one yaw joint) in the benchmark's pitch-yaw gait (pitch 40 deg, yaw 20 deg, 120 deg between
// neighbours, 0.5 Hz): the per-cycle speed, m, averaged over start phases 0, 72, 144, 216, 288
// deg added to every joint as point 5 of issue 14 asks, 10 cycles after 2 s
double pyp_wave_speed(double friction, double dt, int iterations) {
    double sum = 0;
    constexpr int kPhases = 5, kCycles = 10;
    for (int k = 0; k < kPhases; ++k) {
        const double start = 72.0 * k > 180 ? 72.0 * k - 360 : 72.0 * k;
        WorldSpec w = test::chain_world(3, Connection::pitch_yaw);
        w.floor.friction = friction;
        Simulation sim(w, test::options_at(dt, iterations, SimulationOptions{}.solver));
        test::drive(sim, "pitch", test::sine(40, 0.5, 120, start));
        test::drive(sim, "yaw", test::sine(20, 0.5, 120, start));
        sim.run(2);
        Vec3 last = sim.robot_position(0);
        for (int c = 0; c < kCycles; ++c) {
            sim.run(2);
            const Vec3 p = sim.robot_position(0);
            sum += std::hypot(p.x - last.x, p.y - last.y) / (kCycles * kPhases);
            last = p;
        }
    }
    return sum;
}

}  // namespace

TEST_CASE("the 3-module pitch-yaw wave's per-cycle speed is within 3 % at dt/4 and 4x iterations") {
    // friction 1.0, with the engine's solver and floor: 26.3 mm per cycle, dt/4 within 0.3 %
    // (pgs on the floor of 1e5 N/m before 2026-11-30: 6 % below block_nncg)
    for (const double friction : {1.0}) {
        const double base = pyp_wave_speed(friction, 0.001, 20);
        const double fine = pyp_wave_speed(friction, 0.00025, 20);
        const double more = pyp_wave_speed(friction, 0.001, 80);
        CAPTURE(friction, base, fine, more);
        CHECK(base > 0.015);  // it travels: about 26 mm per cycle
        CHECK(std::abs(fine - base) < 0.03 * base);
        CHECK(std::abs(more - base) < 0.03 * base);
    }
}
