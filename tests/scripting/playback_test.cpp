// Simulations that play while a console waits for keystrokes (scripting/src/playback.cpp):
// sim:play(), sim:pause(), sim.speed, sim.delay, sim:status() and LuaHost::pump, paced by a fake
// clock (no test here waits for the real one); the progress hook of long runs.
#include <catch2/catch.hpp>

#include <algorithm>
#include <csignal>
#include <limits>
#include <string>
#include <vector>

#include "gaitlab/simulation.h"
#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// a host whose simulations play against a clock the test moves; `per_tick` > 0 makes every
// tick of every simulation cost that much wall time
struct Fixture {
    LuaFixture lua;
    double now = 1000;
    double per_tick = 0;
    std::vector<std::string> reports;
    Fixture() {
        lua.host.set_clock([this] { return now; });
        lua.host.set_reporter([this](const std::string& m) { reports.push_back(m); });
        lua.host.on_simulation([this](gaitlab::Simulation& sim, int) {
            sim.add_observer([this](const gaitlab::Simulation&) { now += per_tick; });
        });
    }
    // a 4-module caterpillar `name` driven by a sine `ctl_name`
    void snake(const std::string& name, const std::string& extra = "") {
        lua.run(name + "_robot = gaitlab.robot.chain{ name = '" + name + "', modules = 4 }\n" +
                name + "_world = gaitlab.world()\n" + name + "_world:add(" + name + "_robot)\n" +
                name + "_ctl = " + name +
                "_robot:group('pitch'):drive(gaitlab.controllers.sine{ amplitude = 40, "
                "frequency = 0.5, phase = 120 })\n" +
                name + " = gaitlab.simulation{ world = " + name + "_world" + extra + " }");
    }
};

}  // namespace

TEST_CASE("a playing simulation keeps pace with the clock at its speed", "[playback]") {
    Fixture f;
    LuaFixture& lua = f.lua;
    f.snake("sim");
    CHECK(lua.boolean("sim.playing") == false);
    CHECK(lua.number("sim.speed") == 1);
    CHECK(lua.number("sim.delay") == 0);
    CHECK(f.lua.host.pump() == kInf);  // nothing plays
    CHECK(f.lua.host.playing() == 0);

    lua.run("sim:play()");
    CHECK(lua.boolean("sim.playing"));
    CHECK(f.lua.host.playing() == 1);
    f.now += 0.5;
    CHECK(f.lua.host.pump() == Approx(0.001));
    CHECK(lua.number("sim.time") == Approx(0.5));
    CHECK(lua.number("sim:status().factor") == Approx(1));

    SECTION("speed 2") {
        lua.run("sim.speed = 2");
        f.lua.host.pump();
        f.now += 0.5;
        CHECK(f.lua.host.pump() == Approx(0.0005));
        CHECK(lua.number("sim.time") == Approx(1.5));
    }
    SECTION("a delay of 10 ms per 1 ms step: about 10 times slower") {
        lua.run("sim.delay = 0.01");
        CHECK(lua.number("sim.delay") == 0.01);
        f.lua.host.pump();
        f.now += 1.1;
        CHECK(f.lua.host.pump() == Approx(0.011));
        CHECK(lua.number("sim.time") == Approx(0.6));
    }
    SECTION("paused, it stays where it is") {
        lua.run("sim:pause()");
        CHECK(lua.boolean("sim.playing") == false);
        f.now += 1;
        CHECK(f.lua.host.pump() == kInf);
        CHECK(lua.number("sim.time") == Approx(0.5));
        CHECK(f.lua.host.playing() == 0);
    }
    SECTION("step, run and reset work on a playing simulation") {
        lua.run("sim:step(100)  sim:run(0.4)");
        CHECK(lua.number("sim.time") == Approx(1.0));
        f.now += 0.1;
        f.lua.host.pump();  // paces from where it is now
        f.now += 0.1;
        f.lua.host.pump();
        CHECK(lua.number("sim.time") == Approx(1.1));
        lua.run("sim:reset()");
        CHECK(lua.boolean("sim.playing"));
        f.lua.host.pump();
        f.now += 0.25;
        f.lua.host.pump();
        CHECK(lua.number("sim.time") == Approx(0.25));
    }
}

TEST_CASE("pump does a bounded slice of work and lets slow simulations fall behind", "[playback]") {
    Fixture f;
    LuaFixture& lua = f.lua;
    f.snake("sim");
    f.per_tick = 0.001;  // every tick costs 1 ms of wall time

    SECTION("as fast as possible: one slice per pump") {
        lua.run("sim.speed = math.huge  sim:play()");
        CHECK(lua.number("sim.speed") == kInf);
        CHECK(f.lua.host.pump() == 0);
        // the default slice: 20 ms, so 20 ticks (21 as the clock's rounding goes)
        const long long first = lua.integer("sim.ticks");
        CHECK(first >= 20);
        CHECK(first <= 21);
        f.lua.host.set_pump_slice(0.005);
        f.lua.host.pump();
        CHECK(lua.integer("sim.ticks") - first >= 5);
        CHECK(lua.integer("sim.ticks") - first <= 6);
    }
    SECTION("a simulation twice as slow as real time runs at half speed, and says so") {
        f.per_tick = 0.002;
        lua.run("sim:play()");
        f.now += 0.1;
        CHECK(f.lua.host.pump() == 0);          // behind
        CHECK(lua.integer("sim.ticks") >= 10);  // 20 ms of work
        CHECK(lua.integer("sim.ticks") <= 11);
        // a console calls again when told (it waits as long as pump says)
        for (int i = 0; i < 100; ++i)
            f.now += f.lua.host.pump();
        CHECK(lua.number("sim:status().factor") == Approx(0.5).margin(0.02));
        CHECK_THAT(lua.string("tostring(sim:status())"),
                   Catch::Contains("playing at 1x real time, measured 0.50x real time"));
    }
}

TEST_CASE("two simulations play independently", "[playback]") {
    Fixture f;
    LuaFixture& lua = f.lua;
    f.snake("a");
    f.snake("b");
    lua.run("a:play()  b.speed = 3  b:play()");
    CHECK(f.lua.host.playing() == 2);
    f.now += 0.2;
    f.lua.host.pump();
    CHECK(lua.number("a.time") == Approx(0.2));
    CHECK(lua.number("b.time") == Approx(0.6));
    lua.run("a:pause()");
    f.now += 0.2;
    f.lua.host.pump();
    CHECK(lua.number("a.time") == Approx(0.2));
    CHECK(lua.number("b.time") == Approx(1.2));
    CHECK(f.lua.host.playing() == 1);
}

TEST_CASE("a playing simulation whose handle is gone goes on playing", "[playback]") {
    Fixture f;
    LuaFixture& lua = f.lua;
    f.snake("sim");
    lua.run("sim:play()  sim = nil  collectgarbage()  collectgarbage()");
    f.now += 0.3;
    f.lua.host.pump();
    CHECK(lua.number("sim_robot:displacement():norm()") > 0);
    CHECK(f.lua.host.playing() == 1);
}

TEST_CASE("speed and delay reject bad values with a clear message", "[playback]") {
    Fixture f;
    LuaFixture& lua = f.lua;
    f.snake("sim");
    const std::string speed =
        "test:1: sim.speed: a real-time factor > 0 expected (math.huge: as "
        "fast as possible), got ";
    CHECK(lua.error_of("sim.speed = 0") == speed + "0");
    CHECK(lua.error_of("sim.speed = -2") == speed + "-2");
    CHECK(lua.error_of("sim.speed = 0/0") == speed + "nan");
    CHECK(lua.error_of("sim.speed = -math.huge") == speed + "-inf");
    CHECK(lua.error_of("sim.speed = 'fast'") == "test:1: sim.speed: number expected, got string");
    CHECK(lua.error_of("sim.speed = nil") == "test:1: sim.speed: number expected, got nil");
    CHECK(lua.number("sim.speed") == 1);
    lua.run("sim.speed = '2'");  // a numeric string is a number, as everywhere in Lua
    CHECK(lua.number("sim.speed") == 2);
    const std::string delay = "test:1: sim.delay: seconds in [0, 10] expected, got ";
    CHECK(lua.error_of("sim.delay = -1") == delay + "-1");
    CHECK(lua.error_of("sim.delay = 0/0") == delay + "nan");
    CHECK(lua.error_of("sim.delay = 1e300") == delay + "1e+300");
    CHECK(lua.error_of("sim.delay = math.huge") == delay + "inf");
    CHECK(lua.error_of("sim.delay = {}") == "test:1: sim.delay: number expected, got table");
    CHECK(lua.number("sim.delay") == 0);
    CHECK(lua.error_of("sim.playing = true") ==
          "test:1: sim.playing is read-only: call sim:play() or sim:pause()");
    CHECK(lua.error_of("sim.time = 3") ==
          "test:1: cannot set field 'time' of a gaitlab.Simulation (only speed and delay can be "
          "set)");
    CHECK(lua.error_of("sim[1] = 3") ==
          "test:1: cannot set a number key of a gaitlab.Simulation (only speed and delay can be "
          "set)");
    CHECK(lua.error_of("sim.play(3)") ==
          "test:1: bad argument #1 to 'play' (gaitlab.Simulation expected, got number)");
    // the smallest and largest values that make sense still work
    lua.run("sim.speed = 1e-9  sim.delay = 10  sim:play()");
    f.now += 100;
    CHECK(f.lua.host.pump() > 0);
    CHECK(lua.integer("sim.ticks") == 0);
}

TEST_CASE("a controller failing while it plays pauses the simulation, and a fix plays on",
          "[playback]") {
    TempDir dir("playback_fail");
    const std::string file = dir.file("wobble.lua");
    // fails from its 10th step on while `broken`
    write_text(file, R"(return gaitlab.controller{ name = "wobble",
  params = { broken = { 1, min = 0, max = 1 } },
  values = { "n" },
  step = function(self, dt)
    for m = 1, self.joints do
      self.n[m] = self.n[m] + 1
      self:set_angle(m, 20)
      if self.broken > 0 and self.n[m] >= 10 then error("wobble broke") end
    end
  end,
}
)");
    Fixture f;
    LuaFixture& lua = f.lua;
    f.lua.host.set_reload_interval(0);
    lua.run("FILE = '" + file + "'");
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 3 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group("pitch"):drive(gaitlab.controller.load(FILE)())
        sim = gaitlab.simulation{ world = world }
        sim:play()
    )");
    f.now += 1;
    // never throws, and nothing plays any more; but the controller file is watched, so the
    // pump asks to be called again at the reload interval (0 here, so its floor, 0.05 s): a
    // console waiting for a line goes on checking, and a fix saved meanwhile reloads then,
    // not at the next command typed (returning infinity left the first sim:play() refused)
    CHECK(f.lua.host.pump() == Approx(0.05));
    CHECK(lua.boolean("sim.playing") == false);
    CHECK(lua.integer("sim.ticks") == 270);  // the 10th control step, at tick 270, failed
    REQUIRE(f.reports.size() == 1);
    CHECK_THAT(f.reports[0],
               Catch::StartsWith("simulation 1 paused at t = 0.270 s: controller 'wobble' "
                                 "failed: " +
                                 file + ":8: wobble broke\nstack traceback:"));
    CHECK(lua.string("sim:status().controllers[1].state") == "failed");
    CHECK(lua.error_of("sim:play()") ==
          "test:1: cannot play simulation 1: controller 'wobble' failed (" + file +
              ":8: wobble broke); save a fix to its file (it reloads) or call sim:reset()");
    // the student saves a fix: it reloads at the next pump and revives the controller
    write_text(file, R"(return gaitlab.controller{ name = "wobble",
  params = { broken = { 1, min = 0, max = 1 } },
  values = { "n" },
  step = function(self, dt)
    for m = 1, self.joints do
      self.n[m] = self.n[m] + 1
      self:set_angle(m, -25)
    end
  end,
}
)");
    f.lua.host.pump();
    CHECK(lua.boolean("ctl.failed") == false);
    lua.run("sim:play()");
    f.now += 0.5;
    f.lua.host.pump();
    CHECK(lua.number("sim.time") == Approx(0.77));
    CHECK(lua.number("robot:joints()[1].target") == Approx(-25));
    CHECK(lua.string("sim:status().controllers[1].state") == "running");
}

TEST_CASE("a controller failing under 'pause' pauses the playing simulation", "[playback]") {
    Fixture f;
    LuaFixture& lua = f.lua;
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 3 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group("pitch"):drive(gaitlab.controller{ name = "bad",
          step = function(self, dt)
            self.t = (self.t or 0) + dt
            if self.t > 0.1 then error("bad step") end
          end }())
        sim = gaitlab.simulation{ world = world, on_controller_error = "pause" }
        sim:play()
    )");
    f.now += 1;
    f.lua.host.pump();
    CHECK(lua.boolean("sim.playing") == false);
    REQUIRE(f.reports.size() == 2);
    CHECK_THAT(f.reports[0], Catch::StartsWith("controller 'bad' failed: test:8: bad step"));
    // its 4th step (t = 0.09 s) failed; the tick went on, then the simulation paused
    CHECK(f.reports[1] == "simulation 1 paused at t = 0.091 s (a controller failed)");
    // under 'pause' the simulation runs on with the failed group holding, as sim:run does
    lua.run("sim:play()");
    f.now += 0.1;
    f.lua.host.pump();
    CHECK(lua.number("sim.time") == Approx(0.191));
}

TEST_CASE("a simulation that failed plays again only after a reset", "[playback]") {
    Fixture f;
    LuaFixture& lua = f.lua;
    f.snake("sim");
    // a fault of the simulation itself, as a diverging step raises it
    lua.run("sim:play()");
    bool armed = true;
    gaitlab::Simulation* raw = nullptr;
    f.lua.host.on_simulation([&](gaitlab::Simulation& s, int) { raw = &s; });
    f.snake("other");
    REQUIRE(raw != nullptr);
    raw->add_pre_tick([&](gaitlab::Simulation& s) {
        if (armed && s.ticks() == 100) throw gaitlab::Error("physics fell apart");
    });
    lua.run("other:play()");
    f.now += 0.5;
    CHECK(f.lua.host.pump() == Approx(0.001));  // the other one plays on
    CHECK(lua.boolean("other.playing") == false);
    CHECK(lua.number("sim.time") == Approx(0.5));
    REQUIRE(f.reports.size() == 1);
    CHECK(f.reports[0] ==
          "simulation 2 failed at t = 0.100 s and was paused (sim:reset() to play it again): "
          "physics fell apart");
    CHECK(lua.error_of("other:play()") ==
          "test:1: cannot play simulation 2: it failed at t = 0.100 s (physics fell apart); call "
          "sim:reset() first");
    CHECK(lua.string("other:status().failure") == "failed at t = 0.100 s (physics fell apart)");
    armed = false;
    lua.run("other:reset()  other:play()");
    f.now += 0.2;
    f.lua.host.pump();
    CHECK(lua.number("other.time") == Approx(0.2));
}

TEST_CASE("an interrupt pauses every playing simulation", "[playback]") {
    Fixture f;
    LuaFixture& lua = f.lua;
    f.snake("a");
    f.snake("b");
    lua.run("a:play()  b:play()");
    f.now += 0.1;
    f.lua.host.pump();
    f.lua.host.interrupt(SIGINT);
    f.now += 0.1;
    CHECK(f.lua.host.pump() == kInf);
    CHECK(f.lua.host.playing() == 0);
    CHECK(f.reports ==
          std::vector<std::string>{"simulation 1 paused at t = 0.100 s: interrupted (SIGINT)",
                                   "simulation 2 paused at t = 0.100 s: interrupted (SIGINT)"});
    f.lua.host.clear_interrupt();
    lua.run("a:play()  b:play()");
    CHECK(f.lua.host.pause_all() == 2);  // what a console does at Ctrl-C, quietly
    CHECK(f.lua.host.playing() == 0);
    CHECK(f.reports.size() == 2);
    lua.run("a:play()");
    f.now += 0.1;
    f.lua.host.pump();
    CHECK(lua.number("a.time") == Approx(0.2));
    CHECK(lua.number("b.time") == Approx(0.1));
}

TEST_CASE("a parameter changed while playing acts from the next tick and is recorded",
          "[playback]") {
    TempDir dir("playback_event");
    Fixture f;
    LuaFixture& lua = f.lua;
    f.snake("sim", ", record = '" + dir.file("run") + "'");
    lua.run("sim:play()");
    f.now += 0.3;
    f.lua.host.pump();
    const long long at = lua.integer("sim.ticks");
    lua.run("sim_ctl:set('phase', 90, 'console')");
    lua.run("sim_ctl.amplitude = 30");
    f.now += 0.3;
    f.lua.host.pump();
    CHECK(lua.number("sim.time") == Approx(0.6));
    CHECK(lua.number("sim:status().controllers[1].params[3].value") == 90);
    f.lua.host.finish();
    lua.run("ev = gaitlab.data.open('" + dir.file("run") + "'):events()");
    REQUIRE(lua.integer("#ev") == 2);
    CHECK(lua.string("ev[1].kind") == "param");
    CHECK(lua.string("ev[1].origin") == "console");
    CHECK(lua.string("ev[1].name") == "sine.phase");
    CHECK(lua.number("ev[1].value") == 90);
    CHECK(lua.integer("ev[1].tick") == at);
    CHECK(lua.string("ev[2].origin") == "script");
    CHECK(lua.integer("ev[2].tick") == at);
}

TEST_CASE("sim:status() says where a simulation stands", "[playback]") {
    Fixture f;
    LuaFixture& lua = f.lua;
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-yaw" }
        world = gaitlab.world()
        world:add(robot, { yaw = 30 })
        ctl = robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40 })
        sim = gaitlab.simulation{ world = world }
        s = sim:status()
    )");
    CHECK(lua.integer("s.simulation") == 1);
    CHECK(lua.number("s.time") == 0);
    CHECK(lua.boolean("s.playing") == false);
    CHECK(lua.boolean("s.factor == nil"));
    CHECK(lua.string("s.controllers[1].name") == "sine");
    CHECK(lua.string("s.controllers[1].robot") == "snake");
    CHECK(lua.string("table.concat(s.controllers[1].joints, ',')") == "1,3");
    CHECK(lua.string("s.controllers[1].state") == "running");
    CHECK(lua.string("s.controllers[1].params[1].name") == "amplitude");
    CHECK(lua.number("s.controllers[1].params[1].value") == 40);
    CHECK(lua.string("s.controllers[1].params[1].unit") == "deg");
    CHECK(lua.string("s.robots[1].name") == "snake");
    CHECK(lua.number("s.robots[1].heading") == Approx(30));
    CHECK(lua.number("s.robots[1].position.z") > 0);
    CHECK(lua.string("getmetatable(s)") == "gaitlab.Status");
    CHECK(lua.string("tostring(s)") ==
          "simulation 1: t = 0.000 s, paused (speed 1, delay 0 s)\n"
          "  robot snake at (0.125, 0.072, 0.026) m, heading 30.0 deg, turned 0.0 deg\n"
          "  controller sine on snake joints 1, 3, running: amplitude = 40 deg, frequency = "
          "0.5 Hz, phase = 120 deg, phase0 = 0 deg, offset = 0 deg");
    lua.run("sim.speed = math.huge  sim:play()");
    CHECK_THAT(lua.string("tostring(sim:status())"),
               Catch::StartsWith("simulation 1: t = 0.000 s, playing as fast as possible, "
                                 "measuring the real-time factor\n"));
}

TEST_CASE("long runs report their progress to the host's hook", "[playback]") {
    Fixture f;
    LuaFixture& lua = f.lua;
    f.snake("sim");
    std::vector<gaitlab::scripting::RunProgress> seen;
    std::vector<std::string> order;
    f.lua.host.set_progress([&](const gaitlab::scripting::RunProgress& p) {
        seen.push_back(p);
        order.push_back(p.done ? "done" : "line");
    });
    f.per_tick = 0.0005;      // twice as fast as real time
    lua.run("sim:run(0.2)");  // 0.1 s of wall time: too short for a progress line
    CHECK(seen.empty());
    lua.run("sim:run(2)");  // 1 s: a line after 0.5 s, then every 0.25 s, then done
    REQUIRE(seen.size() >= 3);
    CHECK(seen.size() <= 4);
    CHECK(seen[0].start == Approx(0.2));
    CHECK(seen[0].end == Approx(2.2));
    CHECK(seen[0].wall == Approx(0.5).margin(0.04));
    CHECK(seen[0].time - seen[0].start == Approx(2 * seen[0].wall).margin(0.01));
    CHECK(seen.back().done);
    CHECK(seen.back().time == Approx(2.2));
    // print takes the line away first, so output and line never mix
    seen.clear();
    order.clear();
    lua.run(R"(
        talker = gaitlab.robot.chain{ modules = 2 }
        talker_world = gaitlab.world()
        talker_world:add(talker)
        talker:group("all"):drive(gaitlab.controller{ name = "talker",
          step = function(self)
            self.n = (self.n or 0) + 1
            if self.n == 50 then print("hi") end  -- t = 1.47 s, 0.735 s of wall time
          end }())
        talker_sim = gaitlab.simulation{ world = talker_world }
        talker_sim:step(2000)
    )");
    REQUIRE(order.size() >= 4);
    CHECK(order.front() == "line");
    CHECK(order.back() == "done");
    CHECK(std::count(order.begin(), order.end(), "done") == 2);
    // a host without a hook reports nothing, and pumping reports no progress
    f.lua.host.set_progress(nullptr);
    lua.run("sim:run(2)");
    CHECK(seen.size() == order.size());
}

TEST_CASE("a controller file saved while the simulation plays reloads at the next pump",
          "[playback]") {
    TempDir dir("playback_reload");
    const std::string file = dir.file("hold.lua");
    const auto version = [&](int angle) {
        write_text(file,
                   "return gaitlab.controller{ name = 'hold', step = function(self)\n"
                   "  for m = 1, self.joints do self:set_angle(m, " +
                       std::to_string(angle) + ") end\nend }\n");
    };
    version(10);
    Fixture f;
    LuaFixture& lua = f.lua;
    f.lua.host.set_reload_interval(0);
    lua.run("FILE = '" + file + "'");
    lua.run(R"(
        Hold = gaitlab.controller.load(FILE)
        robot = gaitlab.robot.chain{ modules = 3 }
        world = gaitlab.world()
        world:add(robot)
        robot:group("all"):drive(Hold())
        sim = gaitlab.simulation{ world = world }
        sim:play()
    )");
    f.now += 0.1;
    f.lua.host.pump();
    CHECK(lua.number("robot:joints()[1].target") == Approx(10));
    version(-15);
    f.now += 0.1;
    f.lua.host.pump();
    CHECK(lua.integer("Hold.version") == 1);
    CHECK(lua.number("robot:joints()[1].target") == Approx(-15));
    CHECK(lua.number("sim.time") == Approx(0.2));
    CHECK(f.reports.empty());
    // nothing plays: pump still picks up a saved file, and asks to be called again to go on
    // watching it
    lua.run("sim:pause()");
    version(5);
    CHECK(f.lua.host.pump() == Approx(0.05));
    CHECK(lua.integer("Hold.version") == 2);
}
