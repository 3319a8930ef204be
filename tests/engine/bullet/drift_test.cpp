// Issue 14, point 3 ("straight means straight"): a planar gait on a flat floor travels along
// its axis. The pitch-pitch travelling wave, both wave directions, floor friction at the ends of
// 0.3-1.0, at the default settings: its sideways drift stays below 3 % of its travel
// (docs/performance.md, section 12, the drift table; bench/lua/drift.lua measures 2 to 32
// modules at four settings).
#include <catch2/catch.hpp>

#include <cmath>

#include "engine/sim_support.h"
#include "gaitlab/types.h"

using namespace gaitlab;

namespace {

struct Travel {
    double along = 0;   // m, along the chain's axis (x)
    double across = 0;  // m, sideways (y)
};

// the travelling wave of `modules` pitch-pitch modules (40 deg, 0.5 Hz, `phase` deg between
// neighbours) on a floor of friction `mu`: 2 s to settle, then 5 cycles measured
Travel wave_travel(int modules, double phase, double mu) {
    WorldSpec w = test::chain_world(modules, Connection::pitch_pitch);
    w.floor.friction = mu;
    Simulation sim(w);
    test::drive(sim, "pitch", test::sine(40, 0.5, phase));
    sim.run(2);
    const Vec3 start = sim.robot_position(0);
    sim.run(10);
    const Vec3 d = sim.robot_position(0) - start;
    return {d.x, d.y};
}

}  // namespace

TEST_CASE("the pitch-pitch wave goes straight both ways: drift under 3 % of its travel") {
    const int modules = GENERATE(2, 8);
    const double phase = GENERATE(120.0, -120.0);  // +120 travels to -x, -120 (backward) to +x
    const double mu = GENERATE(0.3, 1.0);
    CAPTURE(modules, phase, mu);
    const Travel t = wave_travel(modules, phase, mu);
    CAPTURE(t.along, t.across, 100 * std::abs(t.across) / std::abs(t.along));
    // it travels, the way its wave says: at least 2 cm per cycle
    CHECK(t.along * (phase > 0 ? -1 : 1) > 0.1);
    CHECK(std::abs(t.across) < 0.03 * std::abs(t.along));
}
