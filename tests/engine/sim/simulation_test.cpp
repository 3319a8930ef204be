// Tests for engine/src/sim/simulation.cpp: option and drive validation, placement, summed targets
// of overlapping groups, observers, time and reset, dynamic objects.
#include "gaitlab/simulation.h"

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "engine/sim_support.h"
#include "gaitlab/controllers/offset.h"
#include "gaitlab/error.h"

using namespace gaitlab;
using Catch::Matchers::Equals;

namespace {

SimulationOptions options_with(double dt, int control_every, int solver_iterations) {
    SimulationOptions o;
    o.dt = dt;
    o.control_every = control_every;
    o.solver_iterations = solver_iterations;
    return o;
}

Drive drive_of(std::vector<int> joints, std::shared_ptr<Controller> c) {
    Drive d;
    d.joints = std::move(joints);
    d.controller = std::move(c);
    return d;
}

// positions of every body of robot 0, appended after every control tick
std::vector<double> trace_positions(Simulation& sim, double seconds) {
    std::vector<double> out;
    const int bodies = static_cast<int>(sim.world().robots[0].robot.bodies.size());
    const int every = sim.options().control_every;
    const int id = sim.add_observer([&out, bodies, every](const Simulation& s) {
        if ((s.ticks() - 1) % every != 0) return;
        for (int b = 0; b < bodies; ++b) {
            const Vec3 p = s.body(0, b).pose.position;
            out.insert(out.end(), {p.x, p.y, p.z});
        }
    });
    sim.run(seconds);
    sim.remove_observer(id);
    return out;
}

}  // namespace

TEST_CASE("default simulation options") {
    const SimulationOptions o = default_simulation_options();
    CHECK(o.dt == 0.001);
    CHECK(o.control_every == 30);
    CHECK(o.solver_iterations == 20);
    CHECK(o.seed == 0);
    REQUIRE_NOTHROW(validate(o));
}

TEST_CASE("bad simulation options are rejected with the expected range") {
    const WorldSpec w = test::chain_world(2, Connection::pitch_pitch);
    SECTION("dt zero, negative, too large or not a number") {
        REQUIRE_THROWS_AS(validate(options_with(0, 30, 10)), SpecError);
        REQUIRE_THROWS_WITH(validate(options_with(0, 30, 10)),
                            Equals("dt must be in [1e-06, 0.1] s (got 0)"));
        REQUIRE_THROWS_WITH(validate(options_with(-0.001, 30, 10)),
                            Equals("dt must be in [1e-06, 0.1] s (got -0.001)"));
        REQUIRE_THROWS_WITH(Simulation(w, options_with(0.5, 30, 10)),
                            Equals("dt must be in [1e-06, 0.1] s (got 0.5)"));
        REQUIRE_THROWS_WITH(
            validate(options_with(std::numeric_limits<double>::quiet_NaN(), 30, 10)),
            Equals("dt must be in [1e-06, 0.1] s (got nan)"));
    }
    SECTION("control_every below 1") {
        REQUIRE_THROWS_WITH(Simulation(w, options_with(0.001, 0, 10)),
                            Equals("control_every must be in [1, 1000000] (got 0)"));
        REQUIRE_THROWS_WITH(validate(options_with(0.001, -5, 10)),
                            Equals("control_every must be in [1, 1000000] (got -5)"));
        REQUIRE_THROWS_WITH(validate(options_with(0.001, 1000001, 10)),
                            Equals("control_every must be in [1, 1000000] (got 1000001)"));
    }
    SECTION("solver_iterations outside [1, 10000]") {
        REQUIRE_THROWS_WITH(Simulation(w, options_with(0.001, 30, 0)),
                            Equals("solver_iterations must be in [1, 10000] (got 0)"));
        REQUIRE_THROWS_WITH(validate(options_with(0.001, 30, 10001)),
                            Equals("solver_iterations must be in [1, 10000] (got 10001)"));
    }
    SECTION("the ends of the ranges are allowed") {
        CHECK_NOTHROW(validate(options_with(0.1, 1, 1)));
        CHECK_NOTHROW(validate(options_with(1e-6, 1000, 10000)));
    }
}

TEST_CASE("bad drives are rejected") {
    Simulation sim(test::chain_world(8, Connection::pitch_pitch));
    SECTION("a joint the robot does not have") {
        REQUIRE_THROWS_AS(sim.add_drive(0, drive_of({0, 8}, test::sine(40, 0.5, 120))), SpecError);
        REQUIRE_THROWS_WITH(sim.add_drive(0, drive_of({0, 8}, test::sine(40, 0.5, 120))),
                            Equals("robot 'snake' has no joint 9 (it has joints 1 to 8)"));
        REQUIRE_THROWS_WITH(sim.add_drive(0, drive_of({-1}, test::sine(40, 0.5, 120))),
                            Equals("robot 'snake' has no joint 0 (it has joints 1 to 8)"));
    }
    SECTION("an empty group") {
        REQUIRE_THROWS_WITH(sim.add_drive(0, drive_of({}, test::sine(40, 0.5, 120))),
                            Equals("a joint group needs at least one joint"));
    }
    SECTION("a group naming a joint twice") {
        REQUIRE_THROWS_WITH(sim.add_drive(0, drive_of({1, 2, 1}, test::sine(40, 0.5, 120))),
                            Equals("a joint group names the same joint twice"));
    }
    SECTION("a drive without a controller") {
        REQUIRE_THROWS_WITH(sim.add_drive(0, drive_of({1}, nullptr)),
                            Equals("a drive needs a controller"));
    }
    SECTION("the same controller driving two groups") {
        auto s = test::sine(40, 0.5, 120);
        sim.add_drive(0, drive_of({0, 1}, s));
        REQUIRE_THROWS_WITH(sim.add_drive(0, drive_of({2, 3}, s)),
                            Equals("controller 'sine' already drives a group (create one "
                                   "controller per group)"));
    }
    SECTION("a robot that does not exist") {
        REQUIRE_THROWS_WITH(sim.add_drive(1, drive_of({0}, test::sine(40, 0.5, 120))),
                            Equals("robot index 1 out of range [0, 1)"));
    }
    SECTION("a rejected drive leaves the simulation usable and undriven") {
        CHECK_THROWS(sim.add_drive(0, drive_of({0, 8}, test::sine(40, 0.5, 120))));
        sim.run(0.1);
        for (int j = 0; j < 8; ++j)
            CHECK(sim.joint(0, j).target == 0);
    }
}

TEST_CASE("drives in the world spec are checked when the simulation compiles it") {
    WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
    SECTION("bad joint") {
        w.robots[0].actuation.push_back(drive_of({4}, test::sine(40, 0.5, 120)));
        REQUIRE_THROWS_WITH(Simulation(w),
                            Equals("robot 'snake' has no joint 5 (it has joints 1 to 4)"));
    }
    SECTION("one controller, two groups") {
        auto s = test::sine(40, 0.5, 120);
        w.robots[0].actuation.push_back(drive_of({0, 1}, s));
        w.robots[0].actuation.push_back(drive_of({2, 3}, s));
        REQUIRE_THROWS_WITH(Simulation(w), Equals("controller 'sine' already drives a group "
                                                  "(create one controller per group)"));
    }
    SECTION("valid drives are kept in the compiled spec") {
        w.robots[0].actuation.push_back(drive_of({0, 1, 2, 3}, test::sine(40, 0.5, 120)));
        const Simulation sim(w);
        CHECK(sim.world().robots[0].actuation.size() == 1);
        CHECK(sim.world().robots[0].actuation[0].controller->joints() == 4);
    }
}

TEST_CASE("accessors reject indices out of range") {
    const Simulation sim(test::chain_world(2, Connection::pitch_pitch));
    CHECK(sim.robot_count() == 1);
    REQUIRE_THROWS_WITH(sim.body(0, 3), Equals("body index 3 out of range [0, 3)"));
    REQUIRE_THROWS_WITH(sim.joint(0, -1), Equals("joint index -1 out of range [0, 2)"));
    REQUIRE_THROWS_WITH(sim.robot_position(2), Equals("robot index 2 out of range [0, 1)"));
}

TEST_CASE("run and step advance time in whole ticks") {
    SimulationOptions o;
    o.dt = 0.002;
    Simulation sim(test::chain_world(2, Connection::pitch_pitch), o);
    CHECK(sim.ticks() == 0);
    CHECK(sim.time() == 0);
    sim.step();
    CHECK(sim.ticks() == 1);
    sim.step(9);
    CHECK(sim.ticks() == 10);
    sim.run(0.1);
    CHECK(sim.ticks() == 60);
    CHECK(sim.time() == Approx(0.12));
    sim.run(0.0031);  // rounds to 2 ticks
    CHECK(sim.ticks() == 62);
    REQUIRE_THROWS_WITH(sim.run(-1),
                        Equals("run time must be a non-negative number of seconds (got -1)"));
}

TEST_CASE("run and step never wrap: a run too long for the tick counter is refused",
          "[simulation][limits]") {
    Simulation sim(test::chain_world(2, Connection::pitch_pitch));
    sim.step(3);
    // 1e17 s is 1e20 ticks: std::lround overflowed and the run did nothing
    REQUIRE_THROWS_WITH(sim.run(1e17), Equals("run time must be in [0, 9.0072e+12] s at dt = "
                                              "0.001 s (got 1e+17 s)"));
    REQUIRE_THROWS_WITH(sim.run(std::numeric_limits<double>::infinity()),
                        Equals("run time must be a non-negative number of seconds (got inf)"));
    REQUIRE_THROWS_WITH(sim.run(std::nan("")),
                        Equals("run time must be a non-negative number of seconds (got nan)"));
    REQUIRE_THROWS_WITH(sim.step(1L << 62), Equals("ticks must be in [0, 9007199254740989] (got "
                                                   "4611686018427387904)"));
    REQUIRE_THROWS_WITH(sim.step(-1), Equals("ticks must be in [0, 9007199254740989] (got -1)"));
    CHECK(sim.ticks() == 3);
    CHECK(sim.ticks_for(1.5) == 1500);
    CHECK(checked_ticks("duration", 10, 0.001) == 10000);
    REQUIRE_THROWS_WITH(checked_ticks("duration", 1e16, 0.001),
                        Equals("duration must be in [0, 9.0072e+12] s at dt = 0.001 s (got 1e+16 "
                               "s)"));
}

TEST_CASE("world placement: the tail at the origin, bodies along +x at z = 0.026") {
    const int n = 8;
    SECTION("identity pose") {
        const Simulation sim(test::chain_world(n, Connection::pitch_yaw));
        for (int b = 0; b <= n; ++b) {
            CAPTURE(b);
            const BodyState s = sim.body(0, b);
            const double x = b == 0 ? 0.018 : (b == n ? 0.072 * n - 0.018 : 0.072 * b);
            CHECK(s.pose.position.x == Approx(x).margin(1e-6));
            CHECK(s.pose.position.y == Approx(0).margin(1e-6));
            CHECK(s.pose.position.z == Approx(0.026).margin(1e-6));
            CHECK(s.pose.orientation.w == Approx(1));
        }
        for (int j = 0; j < n; ++j) {
            CHECK(sim.joint(0, j).angle == Approx(0).margin(1e-6));
            CHECK(sim.joint_error(0, j).separation < 1e-6);
        }
        // the centre of mass of a straight chain is its middle
        const Vec3 com = sim.robot_position(0);
        CHECK(com.x == Approx(0.036 * n));
        CHECK(com.y == Approx(0).margin(1e-6));
        CHECK(com.z == Approx(0.026));
        CHECK(sim.robot_displacement(0).norm() == Approx(0).margin(1e-12));
    }
    SECTION("a placed robot is moved and turned by its pose") {
        WorldSpec w = test::chain_world(n, Connection::pitch_pitch);
        w.robots[0].pose.position = {1, 2, 0};
        w.robots[0].pose.orientation = Quat::from_axis_angle({0, 0, 1}, kPi / 2);
        const Simulation sim(w);
        // along +y now, starting at (1, 2)
        const BodyState head = sim.body(0, n);
        CHECK(head.pose.position.x == Approx(1).margin(1e-6));
        CHECK(head.pose.position.y == Approx(2 + 0.072 * n - 0.018).margin(1e-6));
        CHECK(head.pose.position.z == Approx(0.026).margin(1e-6));
        CHECK(sim.joint(0, 3).angle == Approx(0).margin(1e-6));
    }
}

TEST_CASE("overlapping groups add their targets, clamped to the joint range") {
    const double dt = 0.001;
    const int every = 30;
    SimulationOptions o;
    o.dt = dt;
    o.control_every = every;
    Simulation sim(test::chain_world(4, Connection::pitch_yaw), o);
    test::drive(sim, "all", test::sine(20, 0.5, 30));
    auto turn = test::sine(0, 0.5, 0, 0, 15);
    test::drive(sim, "yaw", turn);

    // after the first control tick each joint's clock reads control_dt; the formula is written
    // out here independently of the engine's deg_to_rad
    sim.step();
    const double pi = 3.14159265358979323846, rad = pi / 180;
    const double t = every * dt;
    auto all_deg = [&](int m) { return 20 * std::sin(2 * pi * 0.5 * t + m * 30 * rad); };
    CHECK(sim.joint(0, 0).target == Approx(all_deg(0) * rad));         // pitch: "all" only
    CHECK(sim.joint(0, 1).target == Approx((all_deg(1) + 15) * rad));  // yaw: "all" + offset
    CHECK(sim.joint(0, 2).target == Approx(all_deg(2) * rad));
    CHECK(sim.joint(0, 3).target == Approx((all_deg(3) + 15) * rad));

    // targets hold between control ticks
    const double held = sim.joint(0, 3).target;
    sim.step(every - 1);
    CHECK(sim.joint(0, 3).target == held);
    sim.step();
    CHECK(sim.joint(0, 3).target != held);

    // the sum is clamped to the range: 15 + 85 deg > 90 deg
    turn->set_param("offset", 85);
    sim.step(every);
    const double t2 = 3 * every * dt;
    const double sum = 20 * std::sin(2 * pi * 0.5 * t2 + 30 * rad) + 85;
    REQUIRE(sum > 90);
    CHECK(sim.joint(0, 1).target == Approx(kPi / 2));
}

TEST_CASE("the same joints driven twice are an error naming both controllers") {
    const std::string message =
        "controller 'offset' cannot drive joints 2, 4 of robot 'snake': controller 'sine' "
        "already drives exactly these joints (one controller per group: their targets would add "
        "up; groups that only partly overlap do add)";
    SECTION("added to a simulation") {
        Simulation sim(test::chain_world(4, Connection::pitch_yaw));
        test::drive(sim, "yaw", test::sine(20, 0.5, 30));
        auto offset = std::make_shared<controllers::Offset>();
        CHECK_THROWS_WITH(sim.add_drive(0, drive_of({3, 1}, offset)), message);
        CHECK(sim.drive_count() == 1);
        CHECK(sim.world().robots[0].actuation.size() == 1);
        // a group that shares some of the joints adds up
        sim.add_drive(0, drive_of({1, 2}, offset));
        CHECK(sim.drive_count() == 2);
        sim.step(30);
        CHECK(sim.joint(0, 1).target != 0);
    }
    SECTION("in the spec a simulation is made from") {
        WorldSpec world = test::chain_world(4, Connection::pitch_yaw);
        world.robots[0].actuation.push_back(drive_of({1, 3}, test::sine(20, 0.5, 30)));
        world.robots[0].actuation.push_back(
            drive_of({3, 1}, std::make_shared<controllers::Offset>()));
        try {
            Simulation sim(world);
            FAIL("no error");
        } catch (const SpecError& e) {
            CHECK(std::string(e.what()) == message);
        }
    }
}

TEST_CASE("observers run every tick after the step, until removed") {
    Simulation sim(test::chain_world(2, Connection::pitch_pitch));
    std::vector<long> ticks;
    std::vector<double> times;
    const int id = sim.add_observer([&](const Simulation& s) {
        ticks.push_back(s.ticks());
        times.push_back(s.time());
    });
    int other = 0;
    const int id2 = sim.add_observer([&other](const Simulation&) { ++other; });
    CHECK(id != id2);
    sim.step(5);
    CHECK(ticks == std::vector<long>{1, 2, 3, 4, 5});
    CHECK(times.back() == Approx(0.005));
    sim.remove_observer(id);
    sim.step(5);
    CHECK(ticks.size() == 5);
    CHECK(other == 10);
    sim.remove_observer(12345);  // unknown ids are ignored
    sim.step();
    CHECK(other == 11);
}

TEST_CASE("reset gives back time 0 and the same trajectory") {
    Simulation sim(test::chain_world(8, Connection::pitch_pitch));
    auto s = test::sine(40, 0.5, 120);
    test::drive(sim, "pitch", s);
    const std::vector<double> first = trace_positions(sim, 2.0);
    REQUIRE(sim.robot_displacement(0).norm() > 0.005);
    const double time_value = s->values(controllers::Sine::time)[0];
    CHECK(time_value == Approx(2.01));  // 67 control ticks of 30 ms

    sim.reset();
    CHECK(sim.ticks() == 0);
    CHECK(sim.time() == 0);
    CHECK(sim.robot_displacement(0).norm() == Approx(0).margin(1e-12));
    CHECK(sim.body(0, 0).pose.position.x == Approx(0.018).margin(1e-6));
    CHECK(s->values(controllers::Sine::time)[0] == 0);
    CHECK(s->param("amplitude") == 40);  // parameters are kept

    const std::vector<double> second = trace_positions(sim, 2.0);
    REQUIRE(second.size() == first.size());
    CHECK(second == first);  // bit for bit
}

TEST_CASE("dynamic objects are numbered boxes first, then cylinders") {
    WorldSpec w;
    BoxSpec fixed, moving;
    moving.mass = 1;
    moving.pose.position = {1, 0, 0.05};
    w.boxes = {fixed, moving};
    CylinderSpec c;
    c.mass = 1;
    c.position = {2, 0, 0.05};
    w.cylinders.push_back(c);
    Simulation sim(w);
    REQUIRE(sim.object_count() == 2);
    CHECK(sim.object(0).pose.position.x == Approx(1));
    CHECK(sim.object(1).pose.position.x == Approx(2));
    REQUIRE_THROWS_AS(sim.object(2), SpecError);
}

TEST_CASE("pre-tick hooks run before every tick and may add or remove hooks", "[simulation]") {
    Simulation sim(test::chain_world(2, Connection::pitch_pitch));
    std::vector<long> seen;
    int added = 0, self = 0;
    self = sim.add_pre_tick([&](Simulation& s) {
        seen.push_back(s.ticks());
        if (s.ticks() == 2) {
            // adding a hook from a hook: it runs from the next tick on
            sim.add_pre_tick([&](Simulation&) { ++added; });
        }
        if (s.ticks() == 4) sim.remove_pre_tick(self);  // removing itself
    });
    sim.step(8);
    CHECK(seen == std::vector<long>{0, 1, 2, 3, 4});
    CHECK(added == 5);  // before ticks 3 to 7
}

TEST_CASE("events carry the tick they act from and their origin", "[simulation]") {
    Simulation sim(test::chain_world(3, Connection::pitch_pitch));
    auto sine = test::sine(20, 0.5, 0);
    test::drive(sim, "all", sine);
    std::vector<Event> events;
    const int id =
        sim.add_event_listener([&](const Simulation&, const Event& e) { events.push_back(e); });
    sim.step(10);
    sine->set_param("amplitude", 25);
    sim.add_pre_tick([&](Simulation& s) {
        if (s.ticks() == 15) s.controller(0).set_param("phase", 30, Origin::viewer);
    });
    sim.step(10);
    sim.add_drive(0, Drive{{0}, test::sine(5, 1, 0)});
    sim.reset(Origin::console);
    sim.remove_event_listener(id);
    sine->set_param("amplitude", 30);
    REQUIRE(events.size() == 4);
    CHECK(events[0].kind == EventKind::param);
    CHECK(events[0].tick == 10);
    CHECK(events[0].name == "sine.amplitude");
    CHECK(events[0].value == 25);
    CHECK(events[0].drive == 0);
    CHECK(events[0].origin == Origin::script);
    CHECK(events[1].tick == 15);
    CHECK(events[1].origin == Origin::viewer);
    CHECK(events[1].name == "sine.phase");
    CHECK(events[2].kind == EventKind::drive);
    CHECK(events[2].name == "sine_2");
    CHECK(events[2].tick == 20);
    CHECK(events[3].kind == EventKind::reset);
    CHECK(events[3].origin == Origin::console);
    CHECK(events[3].tick == 20);  // when it happened, not the tick after it (0)
    CHECK(sim.ticks() == 0);
}

TEST_CASE("a controller that outlives its simulation stops telling it", "[simulation]") {
    auto sine = test::sine(20, 0.5, 0);
    {
        Simulation sim(test::chain_world(2, Connection::pitch_pitch));
        test::drive(sim, "all", sine);
        sim.add_event_listener([](const Simulation&, const Event&) {});
    }
    sine->set_param("amplitude", 10);  // no listener left to call
    CHECK(sine->param("amplitude") == 10);
}

namespace {

// a controller that runs `act` (once, or at every step) with the simulation driving it, then
// holds its joints at 0
class Reentrant final : public Controller {
  public:
    Reentrant(Simulation& sim, std::function<void(Simulation&)> act)
        : Controller(ControllerDef{"reentrant", {}, {}}), sim_(sim), act_(std::move(act)) {}
    void step(ControlIO& io) override {
        ++steps;
        if (act_) act_(sim_);
        for (int m = 0; m < io.joints(); ++m)
            io.set_target(m, 0);
    }
    int steps = 0;

  private:
    Simulation& sim_;
    std::function<void(Simulation&)> act_;
};

const char* const kInsideTick = "cannot step the simulation from inside its own tick";

}  // namespace

TEST_CASE(
    "a controller may add drives while the drives step: they act from the next control "
    "tick",
    "[simulation][reentrancy]") {
    const WorldSpec world = test::chain_world(8, Connection::pitch_pitch);
    const int nj = static_cast<int>(world.robots[0].robot.joints.size());
    REQUIRE(nj >= 6);
    Simulation sim(world);
    std::vector<std::shared_ptr<Controller>> added;
    // each step adds one more drive (more than enough to reallocate any vector of drives),
    // each on a group of its own: the k-th drives the joints of the bits of k
    auto adder = std::make_shared<Reentrant>(sim, [&](Simulation& s) {
        if (added.size() >= 40) return;
        added.push_back(test::sine(10, 1, 0));
        std::vector<int> joints;
        for (int j = 0; j < nj; ++j) {
            if ((added.size() >> j) & 1) joints.push_back(j);
        }
        s.add_drive(0, drive_of(joints, added.back()));
    });
    std::vector<int> all(static_cast<size_t>(nj));
    for (int j = 0; j < nj; ++j)
        all[static_cast<size_t>(j)] = j;
    sim.add_drive(0, drive_of(all, adder));
    sim.step(1);  // one control tick: the drive added in it has not stepped yet
    REQUIRE(sim.drive_count() == 2);
    CHECK(sim.controller(1).values(controllers::Sine::time)[0] == 0);
    sim.run(1.5);  // 50 more control ticks
    CHECK(sim.drive_count() == 41);
    CHECK(adder->steps == 51);
    // the first added drive stepped at every control tick after the one that added it
    CHECK(added[0]->values(controllers::Sine::time)[0] == Approx(50 * 0.03));
    // its targets count: a 10 deg sine on joint 0 from the 20 odd-numbered drives (plus the
    // adder's 0)
    const double theta = sim.joint(0, 0).target;
    CHECK(std::abs(theta) > 0);
    CHECK(std::abs(theta) <= deg_to_rad(10) * 20);
}

TEST_CASE("step, run and reset from inside the simulation's own tick are errors",
          "[simulation][reentrancy]") {
    using Catch::Matchers::Contains;
    using Catch::Matchers::StartsWith;
    SECTION("from a controller's step") {
        for (const char* what : {"step", "run", "reset"}) {
            Simulation sim(test::chain_world(3, Connection::pitch_pitch));
            const std::string w = what;
            auto once = std::make_shared<bool>(true);
            auto c = std::make_shared<Reentrant>(sim, [w, once](Simulation& s) {
                if (!*once) return;
                *once = false;
                if (w == "step") s.step(1);
                if (w == "run") s.run(1);
                if (w == "reset") s.reset();
            });
            sim.add_drive(0, drive_of({0, 1, 2}, c));
            CHECK_THROWS_WITH(
                sim.step(5),
                Equals(std::string(kInsideTick) + " (" + w +
                       " called from a controller's step: step, run, reset and clone belong "
                       "between ticks)"));
            CHECK(sim.ticks() == 0);  // the first tick stopped at its think phase
            CHECK(c->failed());
            // the simulation is usable again between ticks
            sim.reset();
            CHECK_NOTHROW(sim.step(40));
            CHECK(c->steps == 3);
        }
    }
    SECTION("from an observer") {
        Simulation sim(test::chain_world(3, Connection::pitch_pitch));
        sim.add_observer([](const Simulation& s) {
            // observers get a const simulation; one that kept a mutable reference must still
            // not get through
            const_cast<Simulation&>(s).run(0.5);
        });
        CHECK_THROWS_WITH(sim.step(3), StartsWith(kInsideTick) && Contains("from an observer"));
        CHECK(sim.ticks() == 1);
    }
    SECTION("from an event listener: a reset that resets again does not recurse") {
        Simulation sim(test::chain_world(3, Connection::pitch_pitch));
        int calls = 0;
        sim.add_event_listener([&calls, &sim](const Simulation&, const Event& e) {
            ++calls;
            if (e.kind == EventKind::reset) sim.reset();
        });
        sim.step(2);
        CHECK_THROWS_WITH(sim.reset(), StartsWith(kInsideTick) &&
                                           Contains("reset called from an event listener"));
        CHECK(calls == 1);
        CHECK(sim.ticks() == 0);
    }
    SECTION("a pre-tick hook may reset between ticks but not step") {
        Simulation sim(test::chain_world(3, Connection::pitch_pitch));
        bool reset_done = false;
        sim.add_pre_tick([&](Simulation& s) {
            if (s.ticks() == 5 && !reset_done) {
                reset_done = true;
                s.reset();
            }
        });
        sim.step(10);
        CHECK(reset_done);
        CHECK(sim.ticks() == 5);  // ticks 0-4, a reset, then ticks 0-4 again
        sim.add_pre_tick([](Simulation& s) { s.step(1); });
        CHECK_THROWS_WITH(sim.step(1),
                          StartsWith(kInsideTick) && Contains("step called from a pre-tick hook"));
    }
}

TEST_CASE("observers and event listeners may add and remove callbacks while they run",
          "[simulation][reentrancy]") {
    Simulation sim(test::chain_world(2, Connection::pitch_pitch));
    std::vector<std::string> calls;
    int self = 0, victim = 0;
    self = sim.add_observer([&](const Simulation& s) {
        calls.push_back("self@" + std::to_string(s.ticks()));
        if (s.ticks() == 1) {
            // adding many (reallocating any vector they live in), removing another and itself
            for (int k = 0; k < 50; ++k)
                sim.add_observer([&calls, k](const Simulation&) {
                    if (k == 49) calls.push_back("added");
                });
            sim.remove_observer(victim);
            sim.remove_observer(self);
        }
    });
    victim = sim.add_observer([&](const Simulation&) { calls.push_back("victim"); });
    sim.step(3);
    CHECK(calls == std::vector<std::string>{"self@1", "added", "added"});

    // listeners: one that adds a listener and removes itself when an event comes
    std::vector<std::string> heard;
    int first = 0;
    first = sim.add_event_listener([&](const Simulation&, const Event&) {
        heard.push_back("first");
        for (int k = 0; k < 20; ++k)
            sim.add_event_listener([&heard, k](const Simulation&, const Event&) {
                if (k == 0) heard.push_back("second");
            });
        sim.remove_event_listener(first);
    });
    sim.reset();
    sim.reset();
    CHECK(heard == std::vector<std::string>{"first", "second"});
}

TEST_CASE("a robot that starts inside an object, the floor or another robot gets a warning",
          "[simulation][overlap]") {
    using Catch::Matchers::Contains;
    SECTION("resting on the floor, on stairs or next to a wall: no warning") {
        WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
        WallSpec wall;
        wall.position = {0.15, 0.036, 0};  // 20 mm thick, touching the robot's side
        w.walls.push_back(wall);
        StairsSpec stairs;
        stairs.position = {1, 0, 0};
        w.stairs.push_back(stairs);
        PlacedRobot on_stairs = w.robots[0];
        on_stairs.robot.name = "climber";
        on_stairs.pose.position = {1.205, 0, 0.04};  // on the second step (0.2 m deep)
        on_stairs.robot = make_chain([] {
            ChainSpec c;
            c.name = "climber";
            c.modules = 2;
            return c;
        }());
        w.robots.push_back(on_stairs);
        Simulation sim(w);
        CHECK(sim.warnings() == std::vector<std::string>{});
    }
    SECTION("inside a box: the warning names the body, the box and the depth") {
        WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
        BoxSpec box;
        box.size = {0.2, 0.2, 0.2};
        box.pose.position = {0.29, 0, 0.1};  // around the head and the last segment
        w.boxes.push_back(box);
        Simulation sim(w);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0],
                   Catch::Matchers::StartsWith("body 'segment3' of robot 'snake' starts 52.0 ") &&
                       Contains("mm deep inside box 1: the contact solver will throw it out "
                                "(place the robot clear of it, e.g. higher)"));
        // warned, not refused: the scene still runs (and the solver pushes the head out)
        CHECK_NOTHROW(sim.run(0.1));
    }
    SECTION("below the floor") {
        WorldSpec w = test::chain_world(2, Connection::pitch_pitch);
        w.robots[0].pose.position.z = -0.1;
        Simulation sim(w);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0], Contains("deep inside the floor"));
    }
    SECTION("inside another robot") {
        WorldSpec w = test::chain_world(2, Connection::pitch_pitch);
        w.robots.push_back(w.robots[0]);
        w.robots[1].pose.position.x = 0.01;
        Simulation sim(w);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0],
                   Contains("of robot 'snake_2'") && Contains("of robot 'snake'"));
    }
    SECTION("a robot's own bodies: only those that collide with each other") {
        // a 3-body chain whose last body reaches back over the middle one (joined to it) and
        // 10 mm into the first (not joined): they collide only with self_collision
        RobotSpec r = test::slender_chain(3, {0.06, 0.03, 0.03}, 0.1, {0, 1, 0}, 1);
        r.bodies[2].size.x = 0.2;
        CHECK(Simulation(test::world_of(r)).warnings().empty());
        r.self_collision = true;
        const Simulation sim(test::world_of(r));
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0],
                   Catch::Matchers::StartsWith("body 'b2' of robot 'slender' starts 10.0 mm deep "
                                               "inside body 'b0' of robot 'slender'"));
    }
    SECTION("a shallow overlap (under 5 mm) is left to the solver") {
        WorldSpec w = test::chain_world(2, Connection::pitch_pitch);
        w.robots[0].pose.position.z = -0.003;
        Simulation sim(w);
        CHECK(sim.warnings().empty());
    }
}

TEST_CASE("a robot passing through itself is warned about once, naming self_collision",
          "[warnings]") {
    using Catch::Matchers::Contains;
    // 6 modules floating, every joint bent to 90 deg: the chain curls beyond a square, its
    // tail into its head (a real robot would stop there)
    const auto folding = [](bool self_collision) {
        WorldSpec w = test::chain_world(6, Connection::pitch_pitch, /*gravity=*/false);
        w.robots[0].robot.self_collision = self_collision;
        return w;
    };
    const auto fold = [](Simulation& sim) {
        test::drive(sim, "all", test::sine(0, 0.5, 0, 0, 90));
    };
    SECTION("without self_collision: one warning, once, as it happens") {
        Simulation sim(folding(false));
        fold(sim);
        std::vector<std::string> told;
        sim.set_warning_handler([&](const std::string& w) { told.push_back(w); });
        CHECK(sim.warnings().empty());
        sim.run(3);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0],
                   Catch::Matchers::StartsWith("robot 'snake' passes through itself at t = 0.") &&
                       Contains("its body 'tail' is ") && Contains(" mm inside its body 'head'") &&
                       Contains("self_collision = true"));
        CHECK(told == sim.warnings());
        // still passing through itself after a reset: not told again
        sim.reset();
        sim.run(3);
        CHECK(sim.warnings().size() == 1);
        CHECK(told.size() == 1);
    }
    SECTION("with self_collision the bodies collide: no warning, the tail stays out of the head") {
        Simulation sim(folding(true));
        fold(sim);
        sim.run(3);
        CHECK(sim.warnings().empty());
        const Vec3 tail = sim.body(0, 0).pose.position;
        const Vec3 head = sim.body(0, 6).pose.position;
        CHECK((head - tail).norm() > 0.055);  // two 60 mm wide bodies side by side
    }
    SECTION("a clone made before warns as its original does; one made after, not again") {
        Simulation sim(folding(false));
        fold(sim);
        sim.run(0.1);
        const std::unique_ptr<Simulation> before = sim.clone();
        sim.run(3);
        before->run(3);
        REQUIRE(before->warnings().size() == 1);
        CHECK(before->warnings() == sim.warnings());
        const std::unique_ptr<Simulation> after = sim.clone();
        after->run(1);
        CHECK(after->warnings() == sim.warnings());
    }
    SECTION("bodies that overlap as built are left as they are") {
        // a 3-body chain whose tail body reaches back 10 mm into the head body, undriven
        RobotSpec r = test::slender_chain(3, {0.06, 0.03, 0.03}, 0.1, {0, 1, 0}, 1);
        r.bodies[2].size.x = 0.2;
        WorldSpec w = test::world_of(r);
        w.gravity = {0, 0, 0};
        w.floor.enabled = false;
        Simulation sim(w);
        sim.run(1);
        CHECK(sim.warnings().empty());
    }
}

TEST_CASE("a body heavy enough to sink into the compliant floor is warned about, once") {
    // resting on 4 corners of 3e3 N/m, 20 cm cubes of 30 and 60 kg sink 24.5 and 49 mm: a
    // tenth of their height and more is warned about, naming the one that sinks deepest for its
    // height
    WorldSpec w = test::chain_world(2, Connection::pitch_pitch);
    for (const double mass : {30.0, 60.0}) {
        BoxSpec cube;
        cube.size = {0.2, 0.2, 0.2};
        cube.mass = mass;
        cube.pose.position = {0, static_cast<double>(w.boxes.size() + 1), 0.1};
        w.boxes.push_back(cube);
    }
    SECTION("on the default floor: the 60 kg cube is named, with a stiffness that holds it") {
        Simulation sim(w);
        REQUIRE(sim.warnings().size() == 1);
        CHECK(sim.warnings()[0] ==
              "box 2 (60 kg) sinks about 49.1 mm into the floor, 25 % of its height: the "
              "floor's springs (3000 N/m per contact point) are soft for it (give the floor a "
              "stiffness of 7.4e+04 N/m or more)");
    }
    SECTION("a stiffer floor, a rigid one, or cubes ten times lighter: no warning") {
        SECTION("stiffer") {
            w.floor.stiffness = 7.4e4;
        }
        SECTION("rigid") {
            w.floor.rigid = true;
        }
        SECTION("lighter") {
            for (BoxSpec& b : w.boxes)
                b.mass /= 10;
        }
        CHECK(Simulation(w).warnings().empty());
    }
    SECTION("a robot body too, by its robot's name") {
        w.boxes.clear();
        for (BodySpec& b : w.robots[0].robot.bodies)
            b.mass = 15;  // 12 mm on 4 corners, a quarter of a module's height
        Simulation sim(w);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0],
                   Catch::Matchers::StartsWith("body '") &&
                       Catch::Matchers::Contains("' of robot 'snake' (15 kg) sinks about 12.3 mm"));
    }
}

TEST_CASE("a world of 100 000 stones builds and steps in well under a second each",
          "[simulation][limits]") {
    // one densely packed field (each stone overlaps hundreds of others): Bullet's broadphase
    // used to pair every stone with its neighbours on insertion and again at every step
    WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
    RubbleSpec r;
    r.count = kMaxRubbleCount;
    r.position = {2, 0, 0};
    w.rubble.push_back(r);
    const auto t0 = std::chrono::steady_clock::now();
    Simulation sim(w);
    const auto t1 = std::chrono::steady_clock::now();
    sim.step(100);
    const auto t2 = std::chrono::steady_clock::now();
    const auto seconds = [](auto d) { return std::chrono::duration<double>(d).count(); };
    // generous bounds (a loaded machine, sanitizers): before, the build took about 10 s and
    // 100 steps minutes
    CHECK(seconds(t1 - t0) < 5);
    CHECK(seconds(t2 - t1) < 5);
    CHECK(sim.warnings().empty());
}

TEST_CASE("settings too coarse for a 3 % accurate gait get one warning naming the setting",
          "[simulation][warning]") {
    using Catch::Matchers::Contains;
    using Catch::Matchers::StartsWith;
    const WorldSpec w = test::chain_world(8, Connection::pitch_pitch);
    SimulationOptions o = default_simulation_options();
    SECTION("the defaults and the limits themselves are quiet") {
        CHECK(Simulation(w, o).warnings().empty());
        o.solver = ConstraintSolver::pgs;
        o.solver_iterations = 15;
        o.dt = 0.0015;
        CHECK(Simulation(w, o).warnings().empty());
    }
    SECTION("pgs: too few iterations") {
        o.solver = ConstraintSolver::pgs;
        o.solver_iterations = 10;
        Simulation sim(w, o);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0],
                   StartsWith("solver_iterations = 10 is below 15: gaits then move more than "
                              "3 %") &&
                       Contains("docs/performance.md"));
        // warned, not refused, and not repeated as the run goes on
        sim.run(0.1);
        CHECK(sim.warnings().size() == 1);
    }
    SECTION("pgs: too large a dt") {
        o.solver = ConstraintSolver::pgs;
        o.dt = 0.002;
        Simulation sim(w, o);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0], StartsWith("dt = 2 ms is above 1.5 ms: gaits then move"));
    }
    SECTION("pgs, both: one warning each") {
        o.solver = ConstraintSolver::pgs;
        o.dt = 0.01;
        o.solver_iterations = 5;
        Simulation sim(w, o);
        REQUIRE(sim.warnings().size() == 2);
        CHECK_THAT(sim.warnings()[0], StartsWith("solver_iterations = 5 is below 15"));
        CHECK_THAT(sim.warnings()[1], StartsWith("dt = 10 ms is above 1.5 ms"));
    }
    SECTION(
        "block_nncg (the default) converges in fewer iterations and at larger steps: its "
        "own limits") {
        CHECK(o.solver == ConstraintSolver::block_nncg);
        o.solver_iterations = 7;
        o.dt = 0.01;
        o.control_every = 1;
        CHECK(Simulation(w, o).warnings().empty());
        o.solver_iterations = 5;
        o.dt = 0.02;
        Simulation sim(w, o);
        REQUIRE(sim.warnings().size() == 2);
        CHECK_THAT(sim.warnings()[0], StartsWith("solver_iterations = 5 is below 7") &&
                                          Contains("with solver = \"block_nncg\""));
        CHECK_THAT(sim.warnings()[1], StartsWith("dt = 20 ms is above 10 ms"));
    }
    SECTION("a world without joints (boxes falling) is not warned about") {
        WorldSpec boxes;
        boxes.boxes.resize(1);
        boxes.boxes[0].mass = 0.1;
        boxes.boxes[0].pose.position = {0, 0, 0.5};
        o.solver_iterations = 4;
        CHECK(Simulation(boxes, o).warnings().empty());
    }
}

TEST_CASE(
    "a long chain bent in two planes gets 8 Newton steps when none are given, and is warned "
    "about without them above dt 0.5 ms or below 40 iterations, naming the settings and the "
    "robot",
    "[simulation][warning]") {
    using Catch::Matchers::Contains;
    using Catch::Matchers::StartsWith;
    SimulationOptions o = default_simulation_options();
    SECTION("newton_steps not given: 8 for a pitch-yaw chain of 13 modules or more, else 0") {
        CHECK(o.newton_steps == kAutomaticNewtonSteps);
        const auto steps = [&](int modules, Connection c) {
            return Simulation(test::chain_world(modules, c), o).options().newton_steps;
        };
        CHECK(steps(16, Connection::pitch_yaw) == 8);
        CHECK(steps(13, Connection::pitch_yaw) == 8);
        CHECK(steps(12, Connection::pitch_yaw) == 0);
        CHECK(steps(32, Connection::pitch_pitch) == 0);
        CHECK(steps(9, Connection::yaw_yaw) == 0);
        // what the choice is made from, for hosts that write files (sim:save)
        CHECK(automatic_newton_steps(test::chain_world(16, Connection::pitch_yaw),
                                     ConstraintSolver::block_nncg) == 8);
        CHECK(automatic_newton_steps(test::chain_world(16, Connection::pitch_yaw),
                                     ConstraintSolver::pgs) == 0);
        // given, they are kept, 0 included
        o.newton_steps = 0;
        CHECK(steps(16, Connection::pitch_yaw) == 0);
        o.newton_steps = 2;
        CHECK(steps(8, Connection::pitch_yaw) == 2);
        // pgs takes none
        o = default_simulation_options();
        o.solver = ConstraintSolver::pgs;
        CHECK(steps(16, Connection::pitch_yaw) == 0);
    }
    SECTION(
        "16 pitch-yaw joints at the defaults: quiet; without the Newton steps one warning "
        "naming both settings and the robot") {
        CHECK(Simulation(test::chain_world(16, Connection::pitch_yaw), o).warnings().empty());
        o.newton_steps = 0;
        Simulation sim(test::chain_world(16, Connection::pitch_yaw), o);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0],
                   StartsWith("dt = 1 ms is above 0.5 ms and solver_iterations = 20 below 40 "
                              "with newton_steps = 0 below 8: robot 'snake' has 16 joints "
                              "bending it in two planes (pitch and yaw)") &&
                       Contains("newton_steps >= 8 (what such a robot gets when newton_steps "
                                "is not given)") &&
                       Contains("sim:check_accuracy()") && Contains("docs/performance.md"));
        sim.run(0.05);
        CHECK(sim.warnings().size() == 1);
    }
    SECTION("each setting alone is named alone") {
        o.newton_steps = 0;
        o.dt = 0.0005;
        Simulation iterations(test::chain_world(16, Connection::pitch_yaw), o);
        REQUIRE(iterations.warnings().size() == 1);
        CHECK_THAT(iterations.warnings()[0],
                   StartsWith("solver_iterations = 20 is below 40 with newton_steps = 0 below 8: "
                              "robot"));
        o.dt = 0.001;
        o.solver_iterations = 40;
        Simulation dt(test::chain_world(16, Connection::pitch_yaw), o);
        REQUIRE(dt.warnings().size() == 1);
        CHECK_THAT(dt.warnings()[0], StartsWith("dt = 1 ms is above 0.5 ms: robot"));
    }
    SECTION(
        "newton_steps >= kLongChainNewtonSteps stand for the iterations, and for dt up to 1 ms on "
        "a floor no stiffer than the default's") {
        o.newton_steps = kLongChainNewtonSteps;
        CHECK(Simulation(test::chain_world(16, Connection::pitch_yaw), o).warnings().empty());
        WorldSpec soft = test::chain_world(16, Connection::pitch_yaw);
        soft.floor.stiffness = 1e3;
        CHECK(Simulation(soft, o).warnings().empty());
        WorldSpec stiff = test::chain_world(16, Connection::pitch_yaw);
        stiff.floor.stiffness = 1e5;
        Simulation on_stiff(stiff, o);
        REQUIRE(on_stiff.warnings().size() == 1);
        CHECK_THAT(on_stiff.warnings()[0],
                   StartsWith("dt = 1 ms is above 0.5 ms on a floor stiffer than the default "
                              "3000 N/m: robot"));
        WorldSpec rigid = test::chain_world(16, Connection::pitch_yaw);
        rigid.floor.rigid = true;
        REQUIRE(Simulation(rigid, o).warnings().size() == 1);
        // up to dt 1 ms, as measured
        o.dt = 0.002;
        o.control_every = 5;
        Simulation coarse(test::chain_world(16, Connection::pitch_yaw), o);
        REQUIRE(coarse.warnings().size() == 1);
        CHECK_THAT(coarse.warnings()[0],
                   StartsWith("dt = 2 ms is above 1 ms with newton_steps = " +
                              std::to_string(kLongChainNewtonSteps) + ": robot") &&
                       Contains("with dt <= 1 ms keep each motion within 2 %"));
        o.control_every = 30;
        o.dt = 0.0005;
        CHECK(Simulation(stiff, o).warnings().empty());
        o.newton_steps = 2;
        Simulation fewer(test::chain_world(16, Connection::pitch_yaw), o);
        REQUIRE(fewer.warnings().size() == 1);
        CHECK_THAT(fewer.warnings()[0],
                   StartsWith("solver_iterations = 20 is below 40 with newton_steps = 2 below " +
                              std::to_string(kLongChainNewtonSteps) + ": robot"));
    }
    SECTION("the finer settings are quiet, and so are planar and 12-joint chains at the defaults") {
        o.newton_steps = 0;
        o.dt = 0.0005;
        o.solver_iterations = 40;
        CHECK(Simulation(test::chain_world(16, Connection::pitch_yaw), o).warnings().empty());
        o = default_simulation_options();
        CHECK(Simulation(test::chain_world(32, Connection::pitch_pitch), o).warnings().empty());
        CHECK(Simulation(test::chain_world(9, Connection::yaw_yaw), o).warnings().empty());
        CHECK(Simulation(test::chain_world(12, Connection::pitch_yaw), o).warnings().empty());
        o.newton_steps = 0;
        CHECK(Simulation(test::chain_world(12, Connection::pitch_yaw), o).warnings().empty());
        CHECK_FALSE(Simulation(test::chain_world(13, Connection::pitch_yaw), o).warnings().empty());
    }
    SECTION("one warning even beyond the general limits (7 iterations, dt 10 ms)") {
        o.newton_steps = 0;
        o.solver_iterations = 5;
        o.dt = 0.02;
        o.control_every = 1;
        Simulation sim(test::chain_world(13, Connection::pitch_yaw), o);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0],
                   StartsWith("dt = 20 ms is above 0.5 ms and solver_iterations = 5 below 40"));
    }
    SECTION("the longest of several such robots is the one named") {
        o.newton_steps = 0;
        WorldSpec w = test::chain_world(14, Connection::pitch_yaw);
        ChainSpec longer;
        longer.name = "long";
        longer.modules = 20;
        longer.connection = Connection::pitch_yaw;
        w.robots.push_back({make_chain(longer), {}, {}});
        w.robots.back().pose.position = {0, 1, 0};
        Simulation sim(w, o);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0], Contains("robot 'long' has 20 joints"));
    }
    SECTION("pgs, which does not converge on such chains, gets a warning naming the solver") {
        o.solver = ConstraintSolver::pgs;
        o.solver_iterations = 80;
        Simulation sim(test::chain_world(16, Connection::pitch_yaw), o);
        REQUIRE(sim.warnings().size() == 1);
        CHECK_THAT(sim.warnings()[0],
                   StartsWith("solver = \"pgs\": robot 'snake' has 16 joints") &&
                       Contains("take solver = \"block_nncg\", which gives such a robot "
                                "newton_steps = " +
                                std::to_string(kLongChainNewtonSteps) +
                                " when they are not given, or dt <= 0.5 ms "
                                "with solver_iterations >= 40"));
    }
}

TEST_CASE("a robot started inside a stone of a rubble field is warned about by the field's name",
          "[simulation][overlap]") {
    WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
    RubbleSpec r;
    r.count = 200;
    r.length = r.width = 0.3;
    r.position = {0.15, 0, 0};
    r.min_height = r.max_height = 0.03;
    w.rubble.push_back(r);
    // static solids of one friction share one body: the warning still names the right one
    WallSpec wall;
    wall.position = {-1, 0, 0};
    w.walls.push_back(wall);
    w.boxes.resize(2);
    w.boxes[0].pose.position = {0, 1, 0.05};
    w.boxes[1].pose.position = {0, -1, 0.05};
    Simulation sim(w);
    REQUIRE(sim.warnings().size() == 1);
    CHECK_THAT(sim.warnings()[0], Catch::Matchers::Contains("mm deep inside rubble 1:"));
    w.rubble.clear();
    w.boxes[1].pose.position = {0.2, 0, 0.05};
    Simulation sim2(w);
    REQUIRE(sim2.warnings().size() == 1);
    CHECK_THAT(sim2.warnings()[0], Catch::Matchers::Contains("mm deep inside box 2:"));
}

TEST_CASE("100 000 static boxes build and step in well under a second each",
          "[simulation][limits]") {
    WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
    // all in one square metre: each overlaps dozens of others
    BoxSpec box;
    box.size = {0.04, 0.04, 0.02};
    for (int k = 0; k < 100000; ++k) {
        box.pose.position = {1.5 + (k % 317) / 317.0, (k / 317 % 317) / 317.0 - 0.5, 0.01};
        w.boxes.push_back(box);
    }
    const auto t0 = std::chrono::steady_clock::now();
    Simulation sim(w);
    const auto t1 = std::chrono::steady_clock::now();
    sim.step(100);
    const auto t2 = std::chrono::steady_clock::now();
    const auto seconds = [](auto d) { return std::chrono::duration<double>(d).count(); };
    CHECK(seconds(t1 - t0) < 5);  // was 6 s on an idle machine, and 3 ms more per step
    CHECK(seconds(t2 - t1) < 5);
}

TEST_CASE("contact points: a chain at rest on the floor carries its weight through them") {
    Simulation sim(test::chain_world(4, Connection::pitch_pitch));
    sim.run(1.0);
    std::vector<ContactPoint> points;
    sim.contacts(points);
    REQUIRE(points.size() >= 4);
    double force = 0;
    for (const ContactPoint& c : points) {
        CHECK(std::abs(c.position.z) < 0.002);  // on the floor
        CHECK(std::abs(std::abs(c.normal.z) - 1) < 1e-6);
        CHECK(c.force >= 0);
        force += c.force;
    }
    // the floor carries the robot: the normal forces add up to its weight
    const double weight = total_mass(sim.world().robots[0].robot) * 9.81;
    CHECK(force == Approx(weight).epsilon(0.05));
}
