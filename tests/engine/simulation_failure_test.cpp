// Tests for the failure policy of engine/src/simulation.cpp: a controller whose step throws is
// marked failed and its joints hold; the run stops (the error leaves step) or continues.
#include <catch2/catch.hpp>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "gaitlab/error.h"
#include "gaitlab/simulation.h"
#include "sim_support.h"

using namespace gaitlab;

namespace {

// a sine wave that throws once the simulation time reaches `fail_at`
class Faulty final : public Controller {
  public:
    explicit Faulty(double fail_at)
        : Controller(ControllerDef{"faulty", {}, {}}), fail_at_(fail_at) {}
    void step(ControlIO& io) override {
        if (io.time() >= fail_at_) throw std::runtime_error("faulty broke");
        ++steps;
        for (int m = 0; m < io.joints(); ++m)
            io.set_target(m, 0.6 * std::sin(6.0 * io.time() + m));
    }
    int steps = 0;

  private:
    double fail_at_;
};

SimulationOptions with_policy(ControllerErrorPolicy policy) {
    SimulationOptions o;
    o.on_controller_error = policy;
    return o;
}

}  // namespace

TEST_CASE("the default policy stops: the error leaves step and the controller is failed") {
    CHECK(default_simulation_options().on_controller_error == ControllerErrorPolicy::stop);
    Simulation sim(test::chain_world(4, Connection::pitch_pitch));
    auto c = std::make_shared<Faulty>(0.3);
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
    auto c = std::make_shared<Faulty>(0.5);
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
    auto c = std::make_shared<Faulty>(0.2);
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
