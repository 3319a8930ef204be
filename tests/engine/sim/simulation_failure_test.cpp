// Tests for the failure policy of engine/src/sim/simulation.cpp: a controller whose step throws is
// marked failed and its joints hold; the run stops (the error leaves step) or continues.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/sim_support.h"
#include "gaitlab/error.h"
#include "gaitlab/simulation.h"

using namespace gaitlab;

// Allocations through operator new larger than `g_refuse_above` bytes fail while it is not 0,
// as they would on a machine without that much memory (this test executable only).
namespace {
std::atomic<std::size_t> g_refuse_above{0};
}  // namespace

// GCC cannot see that these replace the global pair and warns about free() after new
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpragmas"
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t n) {
    const std::size_t limit = g_refuse_above.load(std::memory_order_relaxed);
    if (limit != 0 && n > limit) throw std::bad_alloc();
    if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
    throw std::bad_alloc();
}
// the nothrow form too (Catch uses it), so every scalar new that the deletes below free comes
// from malloc (sanitizers check that the pairs match)
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
    const std::size_t limit = g_refuse_above.load(std::memory_order_relaxed);
    if (limit != 0 && n > limit) return nullptr;
    return std::malloc(n == 0 ? 1 : n);
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
#pragma GCC diagnostic pop

namespace {

SimulationOptions with_policy(ControllerErrorPolicy policy) {
    SimulationOptions o;
    o.on_controller_error = policy;
    return o;
}

}  // namespace

TEST_CASE("the default policy stops: the error leaves step and the controller is failed") {
    CHECK(default_simulation_options().on_controller_error == ControllerErrorPolicy::stop);
    Simulation sim(test::chain_world(4, Connection::pitch_pitch));
    auto c = std::make_shared<test::Faulty>(0.3);
    test::drive(sim, "pitch", c);
    int reported = 0;
    sim.set_controller_error_handler([&](const Controller&, const std::exception&) { ++reported; });
    CHECK_THROWS_WITH(sim.run(1.0), "faulty broke");
    CHECK(c->failed());
    CHECK(c->failure() == "faulty broke");
    CHECK(reported == 0);  // whoever catches the error reports it
    CHECK(sim.time() == Approx(0.3).margin(0.031));
}

TEST_CASE("the continue policy reports once, holds the joints and keeps running") {
    Simulation sim(test::chain_world(4, Connection::pitch_pitch),
                   with_policy(ControllerErrorPolicy::continue_));
    auto c = std::make_shared<test::Faulty>(0.5);
    test::drive(sim, "pitch", c);
    std::vector<std::string> reports;
    sim.set_controller_error_handler([&](const Controller& ctl, const std::exception& e) {
        reports.push_back(ctl.name() + ": " + e.what());
    });
    sim.run(0.5);
    const int steps = c->steps;
    REQUIRE_NOTHROW(sim.run(0.05));
    REQUIRE(c->failed());
    // held at the angles measured when it failed
    std::vector<double> held;
    for (int j = 0; j < 3; ++j)
        held.push_back(sim.joint(0, j).target);
    for (int j = 0; j < 3; ++j)
        CHECK(held[j] == Approx(sim.joint(0, j).angle).margin(0.05));
    REQUIRE_NOTHROW(sim.run(2.0));
    CHECK(reports == std::vector<std::string>{"faulty: faulty broke"});
    CHECK(c->steps == steps);
    CHECK(sim.time() == Approx(2.55));
    for (int j = 0; j < 3; ++j) {
        CHECK(sim.joint(0, j).target == held[j]);
        CHECK(sim.joint(0, j).angle == Approx(held[j]).margin(0.05));
    }
}

TEST_CASE("reset clears the failure and the controller runs again") {
    Simulation sim(test::chain_world(3, Connection::pitch_pitch),
                   with_policy(ControllerErrorPolicy::continue_));
    auto c = std::make_shared<test::Faulty>(0.2);
    test::drive(sim, "pitch", c);
    sim.run(0.5);
    REQUIRE(c->failed());
    sim.reset();
    CHECK_FALSE(c->failed());
    CHECK(c->failure().empty());
    const int steps = c->steps;
    sim.run(0.1);
    CHECK(c->steps > steps);
}

namespace {

// a world without floor where a dynamic box and a dynamic cylinder fall at `g` m/s²
WorldSpec falling_objects(double g) {
    WorldSpec w;
    w.floor.enabled = false;
    w.gravity = {0, 0, -g};
    BoxSpec box;
    box.mass = 1;
    box.pose.position = {5, 0, 0};
    w.boxes.push_back(box);
    CylinderSpec c;
    c.mass = 1;
    c.position = {-5, 0, 0};
    w.cylinders.push_back(c);
    return w;
}

bool finite(const BodyState& s) {
    const Vec3& p = s.pose.position;
    const Quat& q = s.pose.orientation;
    const Vec3& v = s.linear_velocity;
    const Vec3& w = s.angular_velocity;
    for (double x : {p.x, p.y, p.z, q.w, q.x, q.y, q.z, v.x, v.y, v.z, w.x, w.y, w.z}) {
        if (!std::isfinite(x)) return false;
    }
    return true;
}

}  // namespace

TEST_CASE("divergence is caught at the physics step it happens, for dynamic objects too",
          "[divergence]") {
    // 1000 m/s² (the largest gravity allowed) for 10 s: 10 km/s, the speed the check calls
    // diverged. Controllers never run in between (control_every is large), so only a check
    // after every physics step sees it in time.
    SimulationOptions o;
    o.control_every = 1000000;
    Simulation sim(falling_objects(1000), o);
    double fastest = 0;
    bool all_finite = true;
    sim.add_observer([&](const Simulation& s) {
        for (int i = 0; i < s.object_count(); ++i) {
            all_finite = all_finite && finite(s.object(i));
            fastest = std::max(fastest, s.object(i).linear_velocity.norm());
        }
    });
    REQUIRE_THROWS_AS(sim.run(20), DivergenceError);
    // the step that crossed 10 km/s is the one the recorder never saw
    CHECK(sim.time() == Approx(9.999).margin(1e-9));
    CHECK(fastest < 1e4);
    CHECK(all_finite);
    sim.reset();
    REQUIRE_THROWS_WITH(sim.run(20), Catch::Matchers::StartsWith(
                                         "simulation diverged at t = 10.000 s: box 1 is at (5, "
                                         "0, -") &&
                                         Catch::Matchers::Contains("m/s (try a smaller dt"));
}

TEST_CASE("a dynamic cylinder that diverges is named as such", "[divergence]") {
    WorldSpec w = falling_objects(1000);
    w.boxes.clear();
    SimulationOptions o;
    o.control_every = 1000000;
    Simulation sim(w, o);
    REQUIRE_THROWS_WITH(sim.run(20), Catch::Matchers::StartsWith(
                                         "simulation diverged at t = 10.000 s: cylinder 1 is at "
                                         "(-5, 0, -"));
}

namespace {

// sets joint 2's target to `value` at its third step
class BadTarget final : public Controller {
  public:
    explicit BadTarget(double value) : Controller(ControllerDef{"bad", {}, {}}), value_(value) {}
    void step(ControlIO& io) override {
        for (int m = 0; m < io.joints(); ++m)
            io.set_target(m, ++steps >= 3 && m == 1 ? value_ : 0.1);
    }
    int steps = 0;

  private:
    double value_;
};

}  // namespace

TEST_CASE("a target that is not a finite number fails the controller, whatever its policy",
          "[divergence]") {
    for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
        Simulation sim(test::chain_world(3, Connection::pitch_pitch));
        auto c = std::make_shared<BadTarget>(bad);
        test::drive(sim, "pitch", c);
        const std::string shown = std::isnan(bad) ? "nan" : bad > 0 ? "inf rad" : "-inf rad";
        CHECK_THROWS_WITH(
            sim.run(1), "joint 2 of the group: target must be a finite number (got " + shown + ")");
        CHECK(c->failed());
        // the targets the simulation holds stay finite
        for (int j = 0; j < 3; ++j)
            CHECK(std::isfinite(sim.joint(0, j).target));
    }
    Simulation sim(test::chain_world(3, Connection::pitch_pitch),
                   with_policy(ControllerErrorPolicy::continue_));
    auto c = std::make_shared<BadTarget>(std::nan(""));
    test::drive(sim, "pitch", c);
    REQUIRE_NOTHROW(sim.run(1));
    CHECK(c->failed());
    CHECK(std::isfinite(sim.joint(0, 1).target));
}

TEST_CASE("running out of memory while building says so, not std::bad_alloc", "[memory]") {
    WorldSpec w = test::chain_world(2, Connection::pitch_pitch);
    HeightfieldSpec h;
    h.samples_x = h.samples_y = 512;  // 2 MiB of heights, copied when the world is built
    h.heights.assign(512 * 512, 0.0);
    h.position = {5, 0, 0};
    w.heightfields.push_back(h);
    WorldSpec copy = w;  // copied while memory lasts: the constructor takes it by value
    g_refuse_above = 1 << 20;
    std::string message;
    try {
        Simulation sim(std::move(copy));
    } catch (const Error& e) {
        message = e.what();
    } catch (const std::bad_alloc&) {
        message = "std::bad_alloc";
    }
    g_refuse_above = 0;
    CHECK(message ==
          "not enough memory to build the simulation (1 robots with 3 bodies, 1 bodies "
          "of world objects)");
    CHECK_NOTHROW(Simulation(w));  // with the memory back, it builds
}
