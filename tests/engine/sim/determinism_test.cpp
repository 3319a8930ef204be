// Determinism of the whole engine (modelled on Box2D's test_determinism.c): the same gait run
// twice in one process gives bit-identical trajectories, and the trajectory's hash matches a value
// stored here.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "engine/sim_support.h"

using namespace gaitlab;

namespace {

enum class Gait { pitch_pitch, pitch_yaw };

// the pose (position x, y, z and orientation w, x, y, z) of every body of robot 0 after every
// control tick of a 5 s gait
std::vector<double> trajectory(Gait gait) {
    const bool pp = gait == Gait::pitch_pitch;
    Simulation sim(test::chain_world(8, pp ? Connection::pitch_pitch : Connection::pitch_yaw));
    if (pp) {
        test::drive_pitch_pitch_gait(sim, 120);
    } else {
        test::drive_pitch_yaw_gait(sim);
    }
    std::vector<double> out;
    const int bodies = static_cast<int>(sim.world().robots[0].robot.bodies.size());
    const int every = sim.options().control_every;
    sim.add_observer([&out, bodies, every](const Simulation& s) {
        if ((s.ticks() - 1) % every != 0) return;  // the controllers ran in this tick
        for (int b = 0; b < bodies; ++b) {
            const Pose p = s.body(0, b).pose;
            out.insert(out.end(), {p.position.x, p.position.y, p.position.z, p.orientation.w,
                                   p.orientation.x, p.orientation.y, p.orientation.z});
        }
    });
    sim.run(5.0);
    return out;
}

// FNV-1a, 64 bits, over the raw bytes of the doubles
std::uint64_t fnv1a(const std::vector<double>& v) {
    std::uint64_t h = 14695981039346656037ull;
    for (double d : v) {
        unsigned char bytes[sizeof d];
        std::memcpy(bytes, &d, sizeof d);
        for (unsigned char c : bytes) {
            h ^= c;
            h *= 1099511628211ull;
        }
    }
    return h;
}

// The stored hashes depend on the compiler, its flags (-ffp-contract=off is set for every
// gaitlab target), the CPU's floating-point behaviour and the Bullet binary (libbullet-dev 3.24,
// single precision, as Debian ships it). A change of any of them, or any intended change to the
// physics, the servo law or the sine controller, changes them: run this test, check that the
// gaits still pass the behaviour tests in physics_world_test.cpp, then copy the "actual" value
// the failure prints into the constant below.
constexpr std::uint64_t kPitchPitchHash = 0x820e82536ec6bf69ull;
constexpr std::uint64_t kPitchYawHash = 0xf58ae786929f299eull;

std::string hex(std::uint64_t h) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%016llxull", static_cast<unsigned long long>(h));
    return buf;
}

}  // namespace

TEST_CASE("the same gait run twice gives bit-identical trajectories") {
    const Gait gait = GENERATE(Gait::pitch_pitch, Gait::pitch_yaw);
    CAPTURE(gait == Gait::pitch_pitch ? "pitch-pitch" : "pitch-yaw");
    const std::vector<double> a = trajectory(gait);
    const std::vector<double> b = trajectory(gait);
    REQUIRE(a.size() == 167 * 9 * 7);  // 167 control ticks in 5 s, 9 bodies, 7 numbers
    REQUIRE(b.size() == a.size());
    // compare bytes, not values: -0.0 == 0.0 and NaN != NaN would hide differences
    CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

TEST_CASE("the gait trajectories match their stored hashes") {
    const std::uint64_t pp = fnv1a(trajectory(Gait::pitch_pitch));
    const std::uint64_t py = fnv1a(trajectory(Gait::pitch_yaw));
    INFO("pitch-pitch actual " << hex(pp) << ", pitch-yaw actual " << hex(py));
    CHECK(hex(pp) == hex(kPitchPitchHash));
    CHECK(hex(py) == hex(kPitchYawHash));
}
