// Simulation::clone(): a copy whose future is bit-identical to the original's, independent of
// it, able to run on another thread; one spec built into several simulations.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "engine/sim_support.h"
#include "gaitlab/controllers/registry.h"
#include "gaitlab/error.h"

using namespace gaitlab;

namespace {

// everything observable of a simulation, as numbers: time and ticks, every body's pose and
// velocities (robots and objects), every joint's state, every sensor's readings, every
// controller's parameters and per-joint values
std::vector<double> state(const Simulation& sim) {
    std::vector<double> out{sim.time(), static_cast<double>(sim.ticks())};
    const auto body = [&out](const BodyState& s) {
        const Pose& p = s.pose;
        out.insert(out.end(), {p.position.x, p.position.y, p.position.z, p.orientation.w,
                               p.orientation.x, p.orientation.y, p.orientation.z,
                               s.linear_velocity.x, s.linear_velocity.y, s.linear_velocity.z,
                               s.angular_velocity.x, s.angular_velocity.y, s.angular_velocity.z});
    };
    for (int r = 0; r < sim.robot_count(); ++r) {
        const RobotSpec& spec = sim.world().robots[static_cast<size_t>(r)].robot;
        for (int b = 0; b < static_cast<int>(spec.bodies.size()); ++b)
            body(sim.body(r, b));
        for (int j = 0; j < static_cast<int>(spec.joints.size()); ++j) {
            const JointState s = sim.joint(r, j);
            out.insert(out.end(), {s.angle, s.target, s.velocity, s.torque});
        }
        out.push_back(sim.robot_turned(r));
    }
    for (int i = 0; i < sim.object_count(); ++i)
        body(sim.object(i));
    for (int i = 0; i < sim.sensor_count(); ++i) {
        const std::vector<double>& v = sim.sensor_values(i);
        out.insert(out.end(), v.begin(), v.end());
    }
    for (int d = 0; d < sim.drive_count(); ++d) {
        const Controller& c = sim.controller(d);
        for (int p = 0; p < static_cast<int>(c.def().params.size()); ++p)
            out.push_back(c.param(p));
        for (const std::vector<double>& v : c.all_values())
            out.insert(out.end(), v.begin(), v.end());
    }
    out.push_back(sim.contact_count());
    return out;
}

// bit for bit (NaN included), not ==
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// the states after every tick of `seconds` of running
std::vector<std::vector<double>> run_states(Simulation& sim, double seconds) {
    std::vector<std::vector<double>> out;
    const long n = sim.ticks_for(seconds);
    for (long i = 0; i < n; ++i) {
        sim.step(1);
        out.push_back(state(sim));
    }
    return out;
}

// the first tick at which two runs differ, or -1
long first_difference(const std::vector<std::vector<double>>& a,
                      const std::vector<std::vector<double>>& b) {
    if (a.size() != b.size()) return 0;
    for (size_t i = 0; i < a.size(); ++i) {
        if (!same_bits(a[i], b[i])) return static_cast<long>(i);
    }
    return -1;
}

// the 8-module pitch-pitch snake crawling with the classic sine gait
std::unique_ptr<Simulation> crawling_snake() {
    auto sim = std::make_unique<Simulation>(test::chain_world(8, Connection::pitch_pitch));
    test::drive_pitch_pitch_gait(*sim, 120);
    return sim;
}

// two robots (a pitch-yaw snake and a second one beside it), three light boxes between them
// and a static wall ahead
std::unique_ptr<Simulation> robots_and_objects() {
    WorldSpec world = test::chain_world(6, Connection::pitch_yaw);
    PlacedRobot second = world.robots[0];
    second.pose.position = {0.1, 0.25, 0};
    world.robots.push_back(second);
    for (int k = 0; k < 3; ++k) {
        BoxSpec box;
        box.size = {0.06, 0.06, 0.06};
        box.pose.position = {0.1 * k, 0.12, 0.03};
        box.mass = 0.05;
        world.boxes.push_back(box);
    }
    BoxSpec wall;
    wall.size = {0.05, 1.0, 0.1};
    wall.pose.position = {0.5, 0.0, 0.05};
    world.boxes.push_back(wall);
    auto sim = std::make_unique<Simulation>(world);
    test::drive_pitch_yaw_gait(*sim);
    Drive d;
    d.joints = select_joints(sim->world().robots[1].robot, "all");
    d.controller = test::sine(35, 0.8, 60);
    sim->add_drive(1, d);
    return sim;
}

std::shared_ptr<Controller> builtin(const char* name) {
    return std::shared_ptr<Controller>(controllers::make_builtin(name));
}

// a C++ controller that does not implement clone()
class Opaque final : public Controller {
  public:
    Opaque() : Controller(ControllerDef{"opaque", {}, {}}) {}
    void step(ControlIO& io) override {
        for (int m = 0; m < io.joints(); ++m)
            io.set_target(m, 0.1);
    }
};

}  // namespace

TEST_CASE("a clone made mid-gait has the original's future, bit for bit") {
    auto original = crawling_snake();
    original->run(1.3);
    const std::vector<double> before = state(*original);
    std::unique_ptr<Simulation> copy = original->clone();
    // the copy starts where the original is, and cloning did not move the original
    CHECK(same_bits(state(*copy), before));
    CHECK(same_bits(state(*original), before));
    CHECK(copy->time() == original->time());
    CHECK(copy->ticks() == original->ticks());
    CHECK(copy->drive_label(0) == original->drive_label(0));

    const auto a = run_states(*original, 2.0);
    const auto b = run_states(*copy, 2.0);
    CHECK(first_difference(a, b) == -1);
    // the snake crawled in those 2 s: the comparison is of a moving gait, not of a robot at rest
    CHECK(original->robot_displacement(0).norm() > 0.05);
}

TEST_CASE("cloning does not change the original's future") {
    // the physics copy carries the contact solver's warm start and the order of contact pairs:
    // the original, rebuilt by clone(), and its copy go on exactly as a twin that was never
    // cloned, on a flat floor, among objects and another robot, and over rubble, whenever
    // the clone is made
    const auto check = [](const std::function<std::unique_ptr<Simulation>()>& make) {
        for (double t : {0.3, 1.3, 2.7}) {
            CAPTURE(t);
            auto cloned = make();
            auto twin = make();
            cloned->run(t);
            twin->run(t);
            const std::unique_ptr<Simulation> copy = cloned->clone();
            const auto expected = run_states(*twin, 2.0);
            CHECK(first_difference(run_states(*cloned, 2.0), expected) == -1);
            CHECK(first_difference(run_states(*copy, 2.0), expected) == -1);
        }
    };
    SECTION("the snake on a flat floor") {
        check(crawling_snake);
    }
    SECTION("two robots and objects") {
        check(robots_and_objects);
    }
    SECTION("solver block_nncg: two robots and objects, and the rolling pitch-yaw chain") {
        // the solver's block and conjugate-gradient state lives within a step
        check([] {
            WorldSpec world = test::chain_world(6, Connection::pitch_yaw);
            PlacedRobot second = world.robots[0];
            second.pose.position = {0.1, 0.25, 0};
            world.robots.push_back(second);
            BoxSpec box;
            box.size = {0.06, 0.06, 0.06};
            box.pose.position = {0.1, 0.12, 0.03};
            box.mass = 0.05;
            world.boxes.push_back(box);
            SimulationOptions o;
            o.solver = ConstraintSolver::block_nncg;
            auto sim = std::make_unique<Simulation>(world, o);
            test::drive_pitch_yaw_gait(*sim);
            return sim;
        });
        check([] {
            SimulationOptions o;
            o.solver = ConstraintSolver::block_nncg;
            auto sim = std::make_unique<Simulation>(test::chain_world(8, Connection::pitch_yaw), o);
            test::drive(*sim, "pitch", test::sine(40, 0.5, 0));
            test::drive(*sim, "yaw", test::sine(40, 0.5, 0, -90));
            return sim;
        });
    }
    SECTION("over rubble") {
        check([] {
            WorldSpec world = test::chain_world(8, Connection::pitch_yaw);
            RubbleSpec rubble;
            rubble.count = 200;
            rubble.length = 1.5;
            world.rubble.push_back(rubble);
            auto sim = std::make_unique<Simulation>(world);
            test::drive_pitch_yaw_gait(*sim);
            return sim;
        });
    }
    SECTION("over a heightfield, with a box on it") {
        // the box-heightfield collider chooses its points by those the manifold holds
        check([] {
            WorldSpec world = test::chain_world(8, Connection::pitch_yaw);
            world.floor.enabled = false;
            HeightfieldSpec h;
            h.length = h.width = 2;
            h.samples_x = h.samples_y = 101;
            for (int j = 0; j < 101; ++j) {
                for (int i = 0; i < 101; ++i)
                    h.heights.push_back(0.01 * std::cos(0.2 * i) * std::cos(0.3 * j));
            }
            world.heightfields.push_back(h);
            world.robots[0].pose.position.z = 0.011;
            BoxSpec box;
            box.size = {0.03, 0.03, 0.03};
            box.mass = 0.05;
            box.pose.position = {0.3, 0.15, 0.03};
            world.boxes.push_back(box);
            auto sim = std::make_unique<Simulation>(world);
            test::drive_pitch_yaw_gait(*sim);
            return sim;
        });
    }
}

TEST_CASE("every built-in controller is cloned with its oscillator state") {
    for (const std::string& name : controllers::builtin_names()) {
        DYNAMIC_SECTION(name) {
            Simulation sim(test::chain_world(6, Connection::pitch_yaw));
            std::shared_ptr<Controller> c = builtin(name.c_str());
            test::drive(sim, "pitch", c);
            test::drive(sim, "yaw", test::sine(20, 0.7, 90));
            sim.run(0.77);
            const std::unique_ptr<Simulation> copy = sim.clone();
            // the copy's controller is another object with the same values
            CHECK(&copy->controller(0) != &sim.controller(0));
            CHECK(copy->controller(0).all_values() == sim.controller(0).all_values());
            CHECK(first_difference(run_states(sim, 1.0), run_states(*copy, 1.0)) == -1);
        }
    }
}

TEST_CASE("sensors are cloned with their switches, readings and filters") {
    WorldSpec world = test::chain_world(5, Connection::pitch_pitch);
    RobotSpec& robot = world.robots[0].robot;
    SensorSpec imu;
    imu.kind = SensorKind::imu;
    imu.module = 2;
    robot.sensors.push_back(imu);
    SensorSpec contact;
    contact.kind = SensorKind::contact;
    contact.module = 1;
    robot.sensors.push_back(contact);
    SensorSpec range;
    range.kind = SensorKind::range;
    range.module = 4;
    range.direction = {0, 0, -1};
    robot.sensors.push_back(range);
    SensorSpec joint;
    joint.kind = SensorKind::joint;
    joint.joint = 3;
    joint.enabled = false;
    robot.sensors.push_back(joint);
    Simulation sim(world);
    test::drive_pitch_pitch_gait(sim, 120);
    sim.run(0.9);
    sim.set_sensor_enabled(0, false);
    sim.run(0.1);
    sim.set_sensor_enabled(0, true);  // the IMU restarts from rest: its history matters
    sim.step(3);
    const std::unique_ptr<Simulation> copy = sim.clone();
    REQUIRE(copy->sensor_count() == 4);
    for (int i = 0; i < 4; ++i) {
        CHECK(copy->sensor_enabled(i) == sim.sensor_enabled(i));
        CHECK(copy->sensor_values(i) == sim.sensor_values(i));
    }
    CHECK_FALSE(copy->sensor_enabled(3));
    CHECK(first_difference(run_states(sim, 1.0), run_states(*copy, 1.0)) == -1);
}

TEST_CASE("a clone of a world with objects and two robots follows the original") {
    // contacts come and go here (robots meet boxes and each other)
    auto sim = robots_and_objects();
    sim->run(1.1);
    REQUIRE(sim->object_count() == 3);
    const std::unique_ptr<Simulation> copy = sim->clone();
    CHECK(first_difference(run_states(*sim, 2.0), run_states(*copy, 2.0)) == -1);
}

TEST_CASE("a clone is independent of its original") {
    auto original = crawling_snake();
    original->run(1.3);
    const std::unique_ptr<Simulation> changed = original->clone();
    const std::unique_ptr<Simulation> untouched = original->clone();
    changed->controller(0).set_param("amplitude", 20);
    CHECK(original->controller(0).param("amplitude") == 40);
    CHECK(untouched->controller(0).param("amplitude") == 40);
    const auto a = run_states(*original, 2.0);
    const auto b = run_states(*changed, 2.0);
    const auto c = run_states(*untouched, 2.0);
    CHECK(first_difference(a, c) == -1);
    CHECK(first_difference(a, b) == 0);  // the smaller wave acts from the first tick
    // and the other way round: the original changes, its copies do not follow
    original->controller(0).set_param("frequency", 1.5);
    CHECK(untouched->controller(0).param("frequency") == 0.5);
    // events of a copy are its own: the copy's listener hears its changes only
    int heard_copy = 0, heard_original = 0;
    untouched->add_event_listener([&](const Simulation&, const Event&) { ++heard_copy; });
    original->add_event_listener([&](const Simulation&, const Event&) { ++heard_original; });
    untouched->controller(0).set_param("phase", 90);
    CHECK(heard_copy == 1);
    CHECK(heard_original == 0);
    // the copy outlives the original
    original.reset();
    untouched->run(0.5);
    CHECK(untouched->time() == Approx(3.8));
}

// the fastest body's speed, m/s
static double fastest(const Simulation& sim) {
    double v = 0;
    for (int b = 0; b < static_cast<int>(sim.world().robots[0].robot.bodies.size()); ++b)
        v = std::max(v, sim.body(0, b).linear_velocity.norm());
    return v;
}

TEST_CASE("a copy at other settings continues the motion") {
    // the 8-module pitch-yaw rolling gait settled for 4 s, then continued 4 s by itself, by a
    // copy at dt / 4 (the same control period) and by one at 4x the iterations: each copy
    // starts where the original is and rolls on about as far as it does (2.2 and 2.8 % apart
    // over these 2 cycles, Release, 2026-11-30; the mean of 10 cycles and 5 starts is within
    // 0.5 % of the converged one's at these settings, docs/performance.md section 12)
    const auto make = [] {
        auto sim = std::make_unique<Simulation>(test::chain_world(8, Connection::pitch_yaw),
                                                test::options_at(0.001, 20));
        test::drive(*sim, "pitch", test::sine(40, 0.5, 0));
        test::drive(*sim, "yaw", test::sine(40, 0.5, 0, -90));
        return sim;
    };
    auto original = make();
    original->run(4.0);
    const Vec3 start = original->robot_position(0);
    SimulationOptions finer_dt = original->options();
    finer_dt.dt /= 4;
    finer_dt.control_every *= 4;
    SimulationOptions more = original->options();
    more.solver_iterations *= 4;
    const std::unique_ptr<Simulation> dt4 = original->clone(finer_dt);
    const std::unique_ptr<Simulation> it4 = original->clone(more);
    const std::unique_ptr<Simulation> same = original->clone(original->options());
    CHECK(dt4->time() == original->time());
    CHECK(dt4->ticks() == 4 * original->ticks());
    CHECK(dt4->options().dt == 0.00025);
    CHECK(dt4->options().control_every == original->options().control_every * 4);
    CHECK(it4->options().solver_iterations == 80);
    // it starts where the original is: every state but the tick count
    std::vector<double> here = state(*dt4), there = state(*original);
    here.erase(here.begin() + 1);
    there.erase(there.begin() + 1);
    CHECK(same_bits(here, there));
    // the same settings: clone()'s copy, bit for bit
    const std::unique_ptr<Simulation> twin = original->clone();
    CHECK(first_difference(run_states(*same, 0.5), run_states(*twin, 0.5)) == -1);
    for (Simulation* s : {original.get(), dt4.get(), it4.get()})
        s->run(4.0);
    const Vec3 moved = original->robot_position(0) - start;
    CHECK(moved.norm() > 0.3);  // it rolled
    for (Simulation* s : {dt4.get(), it4.get()}) {
        const Vec3 d = s->robot_position(0) - start;
        CAPTURE(s->options().dt, s->options().solver_iterations, moved.norm(), d.norm());
        // the heading wanders more: 4 cm apart after 4 s
        CHECK(std::abs(d.norm() - moved.norm()) < 0.05 * moved.norm());
        CHECK(d.x != moved.x);  // its own settings: not the original's steps
    }
}

TEST_CASE("a copy at a finer dt starts from the same contact forces") {
    // an undriven chain at rest: its contacts' warm-start impulses are scaled to the copy's
    // dt, so its first step holds it nearly still (Release, 2026-11-30: its fastest body at
    // 0.18 mm/s after it; with the impulses as they were, 4x too large for the step, 1.1 mm/s)
    Simulation sim(test::chain_world(8, Connection::pitch_yaw), test::options_at(0.004, 20));
    sim.run(2.0);
    SimulationOptions finer = sim.options();
    finer.dt = 0.001;
    finer.control_every *= 4;
    finer.solver_iterations = 2;  // the warm start's part in the step, large
    const std::unique_ptr<Simulation> copy = sim.clone(finer);
    const double before = fastest(sim);
    copy->step(1);
    CAPTURE(before, fastest(*copy));
    CHECK(fastest(*copy) < std::max(2 * before, 5e-4));
}

TEST_CASE("a copy at other settings: bad settings") {
    auto sim = crawling_snake();
    sim->run(0.2005);  // 201 ticks of 1 ms
    const std::vector<double> before = state(*sim);
    SimulationOptions o = sim->options();
    SECTION("another control period") {
        o.dt = 0.0005;
        CHECK_THROWS_WITH(sim->clone(o),
                          "cannot copy the simulation at dt = 0.0005 s, control_every = 30: the "
                          "controllers step every 0.03 s and a copy keeps that (dt x "
                          "control_every = 0.015 s; at dt = 0.0005 s, control_every = 60)");
    }
    SECTION("a time that is not a whole number of the new steps") {
        o.dt = 0.002;
        o.control_every = 15;
        CHECK_THROWS_WITH(sim->clone(o),
                          "cannot copy the simulation at dt = 0.002 s: its time, 0.201 s (201 "
                          "steps of 0.001 s), is not a whole number of steps of 0.002 s");
    }
    SECTION("a setting out of its range") {
        o.solver_iterations = 0;
        CHECK_THROWS_AS(sim->clone(o), SpecError);
    }
    // the original is untouched and runs on as a twin that was never asked
    CHECK(same_bits(state(*sim), before));
    auto twin = crawling_snake();
    twin->run(0.2005);
    CHECK(first_difference(run_states(*sim, 0.3), run_states(*twin, 0.3)) == -1);
}

TEST_CASE("clones run on other threads") {
    // the original and two clones, each stepped on its own thread, reach the states the same
    // simulations reach one after the other
    auto original = crawling_snake();
    original->run(1.3);
    std::unique_ptr<Simulation> copies[2] = {original->clone(), original->clone()};
    copies[1]->controller(0).set_param("phase", 60);
    auto reference = crawling_snake();
    reference->run(1.3);
    std::unique_ptr<Simulation> reference_copy = reference->clone();
    reference_copy->controller(0).set_param("phase", 60);
    const std::vector<std::vector<double>> expected[2] = {run_states(*reference, 1.5),
                                                          run_states(*reference_copy, 1.5)};

    std::vector<std::vector<double>> got[3];
    Simulation* sims[3] = {original.get(), copies[0].get(), copies[1].get()};
    std::vector<std::thread> threads;
    for (int t = 0; t < 3; ++t)
        threads.emplace_back([&, t] { got[t] = run_states(*sims[t], 1.5); });
    for (std::thread& t : threads)
        t.join();
    CHECK(first_difference(got[0], expected[0]) == -1);
    CHECK(first_difference(got[1], expected[0]) == -1);
    CHECK(first_difference(got[2], expected[1]) == -1);
}

TEST_CASE("one spec builds several simulations") {
    WorldSpec world = test::chain_world(8, Connection::pitch_pitch);
    Drive d;
    d.joints = select_joints(world.robots[0].robot, "pitch");
    std::shared_ptr<Controller> sine = test::sine(40, 0.5, 120);
    d.controller = sine;
    world.robots[0].actuation.push_back(d);

    Simulation first(world);
    first.run(0.5);  // the shared controller now has state of its own
    sine->set_param("amplitude", 30);
    Simulation second(world);  // was: "controller 'sine' already drives a group"
    Simulation third(world);
    // the first drives with the controller of the spec; later ones with fresh copies of it,
    // parameters as they are now, state as just bound
    CHECK(&first.controller(0) == sine.get());
    CHECK(&second.controller(0) != sine.get());
    CHECK(second.controller(0).param("amplitude") == 30);
    CHECK(second.controller(0).values(0) == std::vector<double>(8, 0.0));
    CHECK(second.ticks() == 0);
    // the copies are independent of each other and identical in their futures
    third.controller(0).set_param("frequency", 0.5);
    CHECK(first_difference(run_states(second, 1.0), run_states(third, 1.0)) == -1);
    CHECK(second.robot_displacement(0).norm() > 0.005);

    // the same spec after its first simulation is gone works as well
    WorldSpec again = world;
    { Simulation gone(again); }
    Simulation after(again);
    CHECK(after.drive_count() == 1);
}

TEST_CASE("the same controller in two groups of one spec is still refused") {
    WorldSpec world = test::chain_world(6, Connection::pitch_yaw);
    std::shared_ptr<Controller> sine = test::sine(40, 0.5, 120);
    for (const char* role : {"pitch", "yaw"}) {
        Drive d;
        d.joints = select_joints(world.robots[0].robot, role);
        d.controller = sine;
        world.robots[0].actuation.push_back(d);
    }
    CHECK_THROWS_WITH(Simulation(world),
                      "controller 'sine' already drives a group (create one controller per "
                      "group)");
}

TEST_CASE("a controller whose simulation is gone drives the next one itself") {
    WorldSpec world = test::chain_world(4, Connection::pitch_pitch);
    std::shared_ptr<Controller> sine = test::sine(40, 0.5, 120);
    Drive d;
    d.joints = select_joints(world.robots[0].robot, "pitch");
    d.controller = sine;
    world.robots[0].actuation.push_back(d);
    {
        Simulation first(world);
        first.run(0.5);
        CHECK(sine->bound());
    }
    CHECK_FALSE(sine->bound());
    sine->set_param("amplitude", 0);  // tells no simulation: the first is gone
    Simulation next(world);
    CHECK(&next.controller(0) == sine.get());
    next.run(1);
    CHECK(next.robot_displacement(0).norm() < 1e-3);  // its amplitude 0 stopped the gait

    // a simulation that fails to build lets go of the controllers it bound (and stops
    // listening to them: setting a parameter afterwards reaches no freed simulation)
    WorldSpec twice = test::chain_world(6, Connection::pitch_yaw);
    std::shared_ptr<Controller> both = test::sine(40, 0.5, 120);
    for (const char* role : {"pitch", "yaw"}) {
        Drive g;
        g.joints = select_joints(twice.robots[0].robot, role);
        g.controller = both;
        twice.robots[0].actuation.push_back(g);
    }
    CHECK_THROWS(Simulation(twice));
    CHECK_FALSE(both->bound());
    both->set_param("amplitude", 10);
    twice.robots[0].actuation.pop_back();
    Simulation built(twice);
    CHECK(&built.controller(0) == both.get());
}

TEST_CASE("clone: bad uses") {
    SECTION("from inside a tick") {
        auto sim = crawling_snake();
        std::string error;
        sim->add_observer([&error](const Simulation& s) {
            try {
                const_cast<Simulation&>(s).clone();
            } catch (const SpecError& e) {
                error = e.what();
            }
        });
        sim->step(1);
        CHECK(error ==
              "cannot step the simulation from inside its own tick (clone called from an "
              "observer: step, run, reset and clone belong between ticks)");
    }
    SECTION("from a controller's step, which fails under the stop policy") {
        struct Cloner final : Controller {
            Simulation* sim = nullptr;
            Cloner() : Controller(ControllerDef{"cloner", {}, {}}) {}
            void step(ControlIO&) override { sim->clone(); }
        };
        Simulation sim(test::chain_world(4, Connection::pitch_pitch));
        auto c = std::make_shared<Cloner>();
        c->sim = &sim;
        test::drive(sim, "all", c);
        CHECK_THROWS_WITH(sim.step(1),
                          "cannot step the simulation from inside its own tick (clone called "
                          "from a controller's step: step, run, reset and clone belong between "
                          "ticks)");
    }
    SECTION("a controller that cannot be copied") {
        auto sim = crawling_snake();
        Drive opaque;
        opaque.joints = {0, 1};
        opaque.controller = std::make_shared<Opaque>();
        sim->add_drive(0, opaque);
        sim->run(0.2);
        const std::vector<double> before = state(*sim);
        CHECK_THROWS_WITH(sim->clone(),
                          "controller 'opaque' cannot be copied: its C++ class does not "
                          "implement Controller::clone()");
        // the original is untouched and runs on
        CHECK(same_bits(state(*sim), before));
        sim->run(0.1);
        CHECK(sim->time() == Approx(0.3));
    }
    SECTION("a second simulation of a spec whose controller cannot be copied") {
        WorldSpec world = test::chain_world(4, Connection::pitch_pitch);
        Drive d;
        d.joints = {0, 1};
        d.controller = std::make_shared<Opaque>();
        world.robots[0].actuation.push_back(d);
        Simulation first(world);
        CHECK_THROWS_WITH(Simulation(world),
                          "controller 'opaque' cannot be copied: its C++ class does not "
                          "implement Controller::clone()");
        first.run(0.1);  // the first is not disturbed
        CHECK(first.controller(0).bound());
    }
    SECTION("a diverged simulation clones into a copy that reports the same divergence") {
        // a box falling at 1000 m/s² for 10 s passes the 10 km/s the check calls diverged
        WorldSpec w;
        w.floor.enabled = false;
        w.gravity = {0, 0, -1000};
        BoxSpec box;
        box.mass = 1;
        w.boxes.push_back(box);
        SimulationOptions o;
        o.control_every = 1000000;
        Simulation sim(w, o);
        std::string original_error;
        try {
            sim.run(20);
        } catch (const DivergenceError& e) {
            original_error = e.what();
        }
        REQUIRE_THAT(original_error, Catch::Matchers::StartsWith("simulation diverged at t = "
                                                                 "10.000 s: box 1"));
        const std::unique_ptr<Simulation> copy = sim.clone();
        CHECK(same_bits(state(*copy), state(sim)));
        // both hold the diverged state; a further step diverges both the same way
        std::string again;
        try {
            sim.step(1);
        } catch (const DivergenceError& e) {
            again = e.what();
        }
        REQUIRE_THAT(again, Catch::Matchers::StartsWith("simulation diverged"));
        CHECK_THROWS_WITH(copy->step(1), again);
        // the copy can start again from the spec
        copy->reset();
        CHECK(copy->time() == 0);
        copy->run(1);
        CHECK(copy->object(0).linear_velocity.z == Approx(-1000).epsilon(0.01));
    }
    SECTION("a failed controller stays failed in the copy") {
        SimulationOptions o;
        o.on_controller_error = ControllerErrorPolicy::continue_;
        Simulation sim(test::chain_world(4, Connection::pitch_pitch), o);
        struct Failing final : Controller {
            Failing() : Controller(ControllerDef{"failing", {}, {}}) {}
            void step(ControlIO&) override { throw SpecError("broken on purpose"); }
            std::unique_ptr<Controller> clone() const override {
                return std::unique_ptr<Controller>(new Failing(*this));
            }
        };
        test::drive(sim, "all", std::make_shared<Failing>());
        sim.run(0.2);
        REQUIRE(sim.controller(0).failed());
        const std::unique_ptr<Simulation> copy = sim.clone();
        CHECK(copy->controller(0).failed());
        CHECK(copy->controller(0).failure() == "broken on purpose");
        CHECK(first_difference(run_states(sim, 0.5), run_states(*copy, 0.5)) == -1);
    }
}
