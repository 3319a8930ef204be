// The accuracy check (gaitlab/accuracy.h): a world run again at dt / 4 and at 4x the solver
// iterations, each robot's path per gait cycle compared, one warning per setting that moves it
// by more than 3 %.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "engine/sim_support.h"
#include "gaitlab/accuracy.h"

using namespace gaitlab;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

// the caterpillar gait of a 4-module pitch-pitch chain on a floor of friction 0.8, as a
// simulation whose world() holds the drive
std::unique_ptr<Simulation> caterpillar(const SimulationOptions& options) {
    auto sim = std::make_unique<Simulation>(test::chain_world(4, Connection::pitch_pitch), options);
    test::drive_pitch_pitch_gait(*sim, 120);
    return sim;
}

// the control period 10 ms, or every step where dt is longer
SimulationOptions with(ConstraintSolver solver, double dt, int iterations) {
    SimulationOptions o = test::options_at(dt, iterations, solver);
    o.control_every = std::max(1, o.control_every);
    return o;
}

}  // namespace

TEST_CASE("the check passes the defaults on a caterpillar and reports what it ran", "[accuracy]") {
    const auto sim = caterpillar(default_simulation_options());
    const AccuracyReport r = check_accuracy(sim->world(), sim->options(), 6, 2, 0);
    CHECK(r.warnings.empty());
    CHECK(r.dt_checked);
    CHECK(r.finer_dt.dt == 0.00025);
    CHECK(r.finer_dt.control_every == 120);  // the control period kept
    CHECK(r.finer_dt.solver_iterations == 20);
    CHECK(r.more_iterations.solver_iterations == 80);
    CHECK(r.more_iterations.dt == 0.001);
    REQUIRE(r.robots.size() == 1);
    const AccuracyRobot& snake = r.robots[0];
    CHECK(snake.name == "snake");
    // it crawled (about 27 mm per second), and the finer runs agree within 1 %
    CHECK(snake.given.path > 0.15);
    CHECK(std::abs(snake.dt_off) < 1);
    CHECK(std::abs(snake.iterations_off) < 1);
    CHECK(snake.dt_off == Approx(100 * (snake.given.path / snake.finer_dt.path - 1)));
    // the end point and the turn are reported: it crawled along -x without turning
    CHECK(snake.given.displacement.x < -0.15);
    CHECK(std::abs(snake.given.turned) < 0.01);
    // the simulation checked was not run
    CHECK(sim->ticks() == 0);
}

TEST_CASE("settings too coarse for this robot get one warning each, naming the setting",
          "[accuracy][warning]") {
    SECTION("pgs with 2 iterations: dt and iterations both move it about 9 %") {
        const auto sim = caterpillar(with(ConstraintSolver::pgs, 0.001, 2));
        const AccuracyReport r = check_accuracy(sim->world(), sim->options(), 6, 2, 0);
        REQUIRE(r.warnings.size() == 2);
        CHECK_THAT(r.warnings[0], StartsWith("dt = 1 ms: robot 'snake' moves ") &&
                                      Contains("% slower than with dt = 0.25 ms") &&
                                      Contains("from 0 to 6 s, sampled every 2 s") &&
                                      Contains("(dt = 0.25 ms, control_every = 40)"));
        CHECK_THAT(r.warnings[1], StartsWith("solver_iterations = 2: robot 'snake' moves ") &&
                                      Contains("% slower than with solver_iterations = 8") &&
                                      Contains("take more iterations") &&
                                      Contains("docs/performance.md"));
        CHECK(r.robots[0].dt_off < -5);
        CHECK(r.robots[0].iterations_off < -5);
    }
    SECTION("block_nncg at dt 40 ms with 40 iterations: only the iterations") {
        const auto sim = caterpillar(with(ConstraintSolver::block_nncg, 0.04, 40));
        const AccuracyReport r = check_accuracy(sim->world(), sim->options(), 6, 2, 0);
        REQUIRE(r.warnings.size() == 1);
        CHECK_THAT(r.warnings[0], StartsWith("solver_iterations = 40: robot 'snake' moves "));
        CHECK(std::abs(r.robots[0].dt_off) < 3);
        CHECK(r.robots[0].iterations_off < -3);
    }
}

TEST_CASE("the check's settling time leaves the start out of the path", "[accuracy]") {
    const auto sim = caterpillar(default_simulation_options());
    const AccuracyReport all = check_accuracy(sim->world(), sim->options(), 6, 2, 0);
    const AccuracyReport late = check_accuracy(sim->world(), sim->options(), 6, 2, 2);
    CHECK(late.settle == 2);
    CHECK(late.robots[0].given.path < all.robots[0].given.path);
    CHECK(late.robots[0].given.path > 0.5 * all.robots[0].given.path);
    // the ends are those of the same runs
    CHECK(late.robots[0].given.displacement == all.robots[0].given.displacement);
}

TEST_CASE("the check leaves a running simulation as it was", "[accuracy]") {
    auto sim = caterpillar(default_simulation_options());
    auto twin = caterpillar(default_simulation_options());
    sim->run(1);
    twin->run(1);
    check_accuracy(sim->world(), sim->options(), 2, 1, 0);
    CHECK(sim->ticks() == 1000);
    sim->run(1);
    twin->run(1);
    for (int b = 0; b < 4; ++b) {
        CHECK(sim->body(0, b).pose.position == twin->body(0, b).pose.position);
        CHECK(sim->body(0, b).linear_velocity == twin->body(0, b).linear_velocity);
    }
}

TEST_CASE("the check refuses bad arguments, naming them", "[accuracy][bad-input]") {
    const auto sim = caterpillar(default_simulation_options());
    const WorldSpec& w = sim->world();
    const SimulationOptions& o = sim->options();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (double seconds : {0.0, -1.0, nan, inf}) {
        CHECK_THROWS_WITH(check_accuracy(w, o, seconds, 1, 0),
                          StartsWith("the check's seconds must be > 0"));
    }
    for (double settle : {-1.0, 6.0, 7.0, nan}) {
        CHECK_THROWS_WITH(check_accuracy(w, o, 6, 1, settle),
                          StartsWith("the check's settle must be in [0, seconds) = [0, 6) s"));
    }
    for (double cycle : {0.0, 0.0005, 5.5, nan, inf}) {
        CHECK_THROWS_WITH(check_accuracy(w, o, 6, cycle, 1),
                          StartsWith("the check's cycle must be in [dt, seconds - settle] = "
                                     "[0.001, 5] s"));
    }
    // a run whose ticks at dt / 4 would not fit
    CHECK_THROWS_WITH(check_accuracy(w, o, 3e15, 1, 0),
                      StartsWith("the check's seconds must be in"));
    SimulationOptions bad = o;
    bad.solver_iterations = 0;
    CHECK_THROWS_AS(check_accuracy(w, bad, 6, 1, 0), SpecError);
}

TEST_CASE("a dt too small to quarter is not checked, the iterations still are", "[accuracy]") {
    SimulationOptions o = default_simulation_options();
    o.dt = 2e-6;
    o.control_every = 5000;
    const auto sim = caterpillar(o);
    const AccuracyReport r = check_accuracy(sim->world(), sim->options(), 0.002, 0.001, 0);
    CHECK_FALSE(r.dt_checked);
    CHECK(r.finer_dt.dt == o.dt);
    CHECK(r.more_iterations.solver_iterations == 80);
    REQUIRE(r.robots.size() == 1);
    CHECK(r.robots[0].dt_off == 0);
}

TEST_CASE("a controller that fails in the check's runs: as its policy says", "[accuracy]") {
    SimulationOptions o = default_simulation_options();
    auto faulty = [&](ControllerErrorPolicy policy) {
        o.on_controller_error = policy;
        auto sim = std::make_unique<Simulation>(test::chain_world(4, Connection::pitch_pitch), o);
        test::drive(*sim, "pitch", std::make_shared<test::Faulty>(1.0));
        return sim;
    };
    SECTION("stop: the error leaves the check") {
        const auto sim = faulty(ControllerErrorPolicy::stop);
        CHECK_THROWS_WITH(check_accuracy(sim->world(), sim->options(), 4, 1, 0), "faulty broke");
    }
    SECTION("pause: each run ends where it failed, reported to the host, and the check returns") {
        const auto sim = faulty(ControllerErrorPolicy::pause);
        int reports = 0;
        const AccuracyReport r =
            check_accuracy(sim->world(), sim->options(), 4, 1, 0, [&](Simulation& run) {
                run.set_controller_error_handler(
                    [&](const Controller&, const std::exception&) { ++reports; });
            });
        CHECK(reports == 3);
        REQUIRE(r.robots.size() == 1);
        CHECK(r.robots[0].given.path > 0);  // the path up to the failure
    }
    SECTION("continue: the runs go on with the group held") {
        const auto sim = faulty(ControllerErrorPolicy::continue_);
        const AccuracyReport r = check_accuracy(sim->world(), sim->options(), 4, 1, 0);
        REQUIRE(r.robots.size() == 1);
    }
}
