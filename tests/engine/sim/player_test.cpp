// Playing a simulation against a wall clock (engine/src/sim/player.cpp), with a fake clock: no test
// here waits for the real one.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/sim_support.h"
#include "gaitlab/player.h"

using namespace gaitlab;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// a wall clock the test moves, and that each tick may move too (the cost of a step)
struct FakeClock {
    double now = 100;
    double per_tick = 0;
    WallClock clock() {
        return [this] { return now; };
    }
    // ticks of `sim` move the clock by per_tick
    void charge(Simulation& sim) {
        sim.add_observer([this](const Simulation&) { now += per_tick; });
    }
};

std::shared_ptr<Simulation> snake() {
    auto sim = std::make_shared<Simulation>(test::chain_world(4, Connection::pitch_pitch));
    test::drive_pitch_pitch_gait(*sim, 120);
    return sim;
}

// advance with a slice of 20 ms from now
long pump(Player& p, FakeClock& c) {
    return p.advance(c.clock(), c.now + 0.02);
}

}  // namespace

TEST_CASE("a player keeps pace with the wall clock times its speed", "[player]") {
    FakeClock c;
    auto sim = snake();
    Player p(sim);
    CHECK_FALSE(p.playing());
    CHECK(p.wait(c.now) == kInf);
    CHECK(pump(p, c) == 0);  // paused: nothing moves
    c.now += 1;
    CHECK(pump(p, c) == 0);
    CHECK(sim->ticks() == 0);

    p.play(c.now);
    CHECK(p.playing());
    CHECK(p.wait(c.now) == Approx(0.001));  // the first tick is due after one dt
    c.now += 0.5;
    CHECK(pump(p, c) == 500);
    CHECK(sim->time() == Approx(0.5));
    CHECK(p.wait(c.now) == Approx(0.001));
    CHECK(p.measured_speed() == Approx(1));
    c.now += 0.0004;
    CHECK(pump(p, c) == 0);  // not due yet
    CHECK(p.wait(c.now) == Approx(0.0006));

    SECTION("speed 2 runs twice as fast") {
        p.set_speed(2);
        CHECK(p.speed() == 2);
        pump(p, c);  // the pace restarts here
        c.now += 0.5;
        pump(p, c);
        CHECK(sim->time() == Approx(1.5));
        CHECK(p.wait(c.now) == Approx(0.0005));
    }
    SECTION("a delay between steps slows it down") {
        p.set_delay(0.01);
        pump(p, c);
        const double t0 = sim->time();
        c.now += 1.1;  // 100 ticks of 1 ms simulated, each 11 ms of wall time
        pump(p, c);
        CHECK(sim->time() - t0 == Approx(0.1));
        CHECK(p.wait(c.now) == Approx(0.011));
    }
    SECTION("pausing stops it where it is") {
        p.pause();
        c.now += 1;
        CHECK(pump(p, c) == 0);
        CHECK(sim->time() == Approx(0.5));
        CHECK(p.wait(c.now) == kInf);
        // playing again starts from now, not from where it paused
        p.play(c.now);
        c.now += 0.25;
        pump(p, c);
        CHECK(sim->time() == Approx(0.75));
    }
    SECTION("a simulation stepped from outside paces from where it is") {
        sim->step(300);
        c.now += 0.1;
        CHECK(pump(p, c) == 0);  // rebased at this call
        c.now += 0.1;
        CHECK(pump(p, c) == 100);
        CHECK(sim->time() == Approx(0.9));
        sim->reset();
        c.now += 5;
        CHECK(pump(p, c) == 0);
        c.now += 0.2;
        pump(p, c);
        CHECK(sim->time() == Approx(0.2));
    }
}

TEST_CASE("a player does at most a slice of work per call", "[player]") {
    FakeClock c;
    c.per_tick = 0.001;  // every step costs 1 ms of wall time: as slow as real time
    auto sim = snake();
    c.charge(*sim);
    Player p(sim);

    SECTION("as fast as possible is bounded by the slice") {
        p.set_speed(kInf);
        p.play(c.now);
        CHECK(p.wait(c.now) == 0);
        CHECK(pump(p, c) == 20);
        CHECK(pump(p, c) == 20);
        CHECK(p.wait(c.now) == 0);
        for (int i = 0; i < 30; ++i)
            pump(p, c);
        CHECK(p.measured_speed() == Approx(1));  // what this machine manages
    }
    SECTION("a simulation that cannot keep up does not catch up forever") {
        c.per_tick = 0.002;  // twice as slow as real time
        p.play(c.now);
        c.now += 0.1;
        const long first = pump(p, c);  // 10 ticks per 20 ms slice (11 as rounding goes)
        CHECK(first >= 10);
        CHECK(first <= 11);
        CHECK(p.wait(c.now) == 0);  // behind
        // a console calls again when told (it sleeps through any wait)
        for (int i = 0; i < 100; ++i) {
            c.now += p.wait(c.now);
            pump(p, c);
        }
        CHECK(p.measured_speed() == Approx(0.5).margin(0.02));
        // the work it could not do is dropped: once the simulation is fast again, it runs at
        // speed 1 and does not race to make up for the lost time
        c.per_tick = 0;
        pump(p, c);
        c.now += 0.1;
        CHECK(pump(p, c) == 100);
    }
    SECTION("a player that was not called for a while does not race") {
        p.play(c.now);
        c.now += 60;
        CHECK(pump(p, c) == 20);
        const long t = sim->ticks();
        c.per_tick = 0;
        c.now += 0.01;
        CHECK(pump(p, c) == 10);
        CHECK(sim->ticks() - t == 10);
    }
}

TEST_CASE("players of two simulations play independently", "[player]") {
    FakeClock c;
    auto a = snake();
    auto b = snake();
    Player pa(a), pb(b);
    pa.play(c.now);
    pb.set_speed(4);
    pb.play(c.now);
    c.now += 0.25;
    pa.advance(c.clock(), c.now + 1);
    pb.advance(c.clock(), c.now + 1);
    CHECK(a->time() == Approx(0.25));
    CHECK(b->time() == Approx(1.0));
    pa.pause();
    c.now += 0.25;
    pa.advance(c.clock(), c.now + 1);
    pb.advance(c.clock(), c.now + 1);
    CHECK(a->time() == Approx(0.25));
    CHECK(b->time() == Approx(2.0));
}

TEST_CASE("a player rejects a bad speed or delay and keeps the old one", "[player]") {
    Player p(snake());
    const double nan = std::nan("");
    for (double bad : {0.0, -1.0, nan, -kInf}) {
        CHECK_THROWS_AS(p.set_speed(bad), SpecError);
        CHECK(p.speed() == 1);
    }
    CHECK_THROWS_WITH(p.set_speed(0),
                      "speed must be a real-time factor > 0 (inf: as fast as possible), got 0");
    for (double bad : {-1.0, nan, 10.5, kInf, 1e300}) {
        CHECK_THROWS_AS(p.set_delay(bad), SpecError);
        CHECK(p.delay() == 0);
    }
    CHECK_THROWS_WITH(p.set_delay(-1), "delay must be in [0, 10] s, got -1");
    p.set_speed(1e-300);  // absurdly slow is still a speed: nothing is due for ages
    p.play(0);
    CHECK(p.advance([] { return 1e6; }, 2e6) == 0);
    CHECK(p.wait(1e6) > 1e6);
}

TEST_CASE("a failure pauses a player until the simulation is reset", "[player]") {
    FakeClock c;
    auto sim = snake();
    Player p(sim);
    // a hook that fails at the 50th tick, as an interrupt or a diverging step would
    sim->add_pre_tick([](Simulation& s) {
        if (s.ticks() == 50) throw Error("boom");
    });
    p.play(c.now);
    c.now += 1;
    CHECK_THROWS_WITH(pump(p, c), "boom");
    CHECK_FALSE(p.playing());
    CHECK(sim->ticks() == 50);
    p.fail("boom");
    CHECK(p.failure() == "boom");
    sim->reset();
    CHECK(p.failure().empty());
}

TEST_CASE("a controller failing under the pause policy pauses the player", "[player]") {
    struct Failing : Controller {
        Failing() : Controller(ControllerDef{"failing", {}, {}}) {}
        void step(ControlIO& io) override {
            if (io.time() > 0.1) throw std::runtime_error("bad step");
        }
    };
    SimulationOptions o;
    o.on_controller_error = ControllerErrorPolicy::pause;
    auto sim = std::make_shared<Simulation>(test::chain_world(2, Connection::pitch_pitch), o);
    test::drive(*sim, "all", std::make_shared<Failing>());
    FakeClock c;
    Player p(sim);
    p.play(c.now);
    c.now += 1;
    pump(p, c);
    CHECK_FALSE(p.playing());
    CHECK(sim->time() == Approx(0.121));  // the control tick after 0.1 s, then it paused
    CHECK(sim->controller(0).failed());
}
