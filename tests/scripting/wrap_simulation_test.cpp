// gaitlab.simulation: options, stepping and time (scripting/src/wrap_simulation.cpp).
#include <catch2/catch.hpp>

#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::test::LuaFixture;

TEST_CASE("simulation rejects bad options with Lua-worded messages", "[wrap_simulation]") {
    LuaFixture lua;
    lua.run("w = gaitlab.world()");
    const std::string bad = "test:1: bad argument #1 to 'simulation' (";
    CHECK(lua.error_of("gaitlab.simulation{ world = w, dtt = 0.01 }") ==
          bad + "unknown key 'dtt'; did you mean 'dt'?)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, control_evry = 10 }") ==
          bad + "unknown key 'control_evry'; did you mean 'control_every'?)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, record = 3 }") ==
          bad + "field 'record': false, true, a run folder or a table expected, got number)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, record = { each = 3 } }") ==
          bad + "field 'record': unknown key 'each')");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, record = { record_every = 0 } }") ==
          bad + "field 'record': record_every must be in [1, 1000000] (got 0))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, record = { flush_seconds = -1 } }") ==
          bad + "field 'record': flush_seconds must be a non-negative number of seconds)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, record = { series = 'x' } }") ==
          bad + "field 'record': series: list of names, patterns or kinds expected, got string)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, record = '' }") ==
          bad + "field 'record': run folder expected, got an empty string)");
    CHECK(lua.error_of("gaitlab.simulation{}") ==
          bad + "field 'world': gaitlab.World expected, got nil)");
    CHECK(lua.error_of("gaitlab.simulation{ world = 3 }") ==
          bad + "field 'world': gaitlab.World expected, got number)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, dt = 0 }") ==
          bad + "dt must be in [1e-06, 0.1] s (got 0))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, control_every = 0 }") ==
          bad + "control_every must be in [1, 1000000] (got 0))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, control_every = 2.5 }") ==
          bad + "field 'control_every': integer expected, got a fractional number)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, control_every = 1e19 }") ==
          bad + "field 'control_every': integer expected, got 1e+19 (beyond the 64-bit integers))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, dt = 0/0 }") ==
          bad + "dt must be in [1e-06, 0.1] s (got nan))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, seed = -1 }") ==
          bad + "field 'seed': non-negative integer expected)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, solver_iterations = 0 }") ==
          bad + "solver_iterations must be in [1, 10000] (got 0))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, solver = 'fast' }") ==
          bad + "field 'solver': 'pgs' or 'block_nncg' expected, got 'fast')");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, newton_steps = -1 }") ==
          bad + "newton_steps must be in [0, 100] (got -1))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, newton_steps = 101 }") ==
          bad + "newton_steps must be in [0, 100] (got 101))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, newton_steps = 2.5 }") ==
          bad + "field 'newton_steps': integer expected, got a fractional number)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, newton_steps = '4' }") ==
          bad + "field 'newton_steps': integer expected, got string)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, newton_steps = 4, solver = 'pgs' }") ==
          bad +
              "newton_steps = 4 needs solver = 'block_nncg' (got solver = 'pgs'; newton_steps "
              "must be 0 with it))");
    CHECK(lua.error_of("gaitlab.simulation(w)") == bad + "table expected, got gaitlab.World)");
    // without a host that records by default, nothing records unless asked
    lua.run("s = gaitlab.simulation{ world = w, record = false }");
    CHECK(lua.boolean("s.record_dir == nil"));
    lua.run("s = gaitlab.simulation{ world = w }");
    CHECK(lua.boolean("s.record_dir == nil"));
}

TEST_CASE(
    "newton_steps not given are chosen for the world, read back as chosen, and saved so a "
    "file keeps its physics",
    "[wrap_simulation]") {
    gaitlab::test::TempDir dir("newton_auto");
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run(R"(
        function sim_of(modules, connection, o)
          local robot = gaitlab.robot.chain{ name = "snake", modules = modules,
                                             connection = connection }
          robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40 })
          local world = gaitlab.world()
          world:add(robot)
          o = o or {}
          o.world, o.record = world, false
          return gaitlab.simulation(o)
        end
        long, short = sim_of(16, "pitch-yaw"), sim_of(12, "pitch-yaw")
        planar, given = sim_of(32, "pitch-pitch"), sim_of(16, "pitch-yaw", { newton_steps = 0 })
        pgs = sim_of(16, "pitch-yaw", { solver = "pgs" })
    )");
    CHECK(lua.integer("long.newton_steps") == 8);
    CHECK(lua.integer("#long.warnings") == 0);
    CHECK(lua.integer("short.newton_steps") == 0);
    CHECK(lua.integer("planar.newton_steps") == 0);
    CHECK(lua.integer("given.newton_steps") == 0);
    CHECK(lua.integer("#given.warnings") == 1);  // the long-chain warning, naming the settings
    CHECK(lua.integer("pgs.newton_steps") == 0);
    // saved: the chosen number is left out (the file's world chooses it again), a given one
    // that differs is written, 0 included; each file loads into the same physics
    lua.run(R"(
        assert(long:save(DIR .. "/long.xml"))
        assert(given:save(DIR .. "/given.xml"))
        function text(name)
          local f = assert(io.open(DIR .. "/" .. name)) local t = f:read("a") f:close() return t
        end
        long2 = assert(gaitlab.simulation.load(DIR .. "/long.xml"))
        given2 = assert(gaitlab.simulation.load(DIR .. "/given.xml"))
        long:run(1) long2:run(1)
        given:run(1) given2:run(1)
    )");
    CHECK_FALSE(lua.boolean("text('long.xml'):find('newton_steps') ~= nil"));
    CHECK(lua.boolean("text('given.xml'):find('newton_steps=\"0\"') ~= nil"));
    CHECK(lua.integer("long2.newton_steps") == 8);
    CHECK(lua.integer("given2.newton_steps") == 0);
    CHECK(lua.boolean("long:robot('snake'):position() == long2:robot('snake'):position()"));
    CHECK(lua.boolean("given:robot('snake'):position() == given2:robot('snake'):position()"));
    // and the two differ: the Newton steps are in the physics
    CHECK_FALSE(lua.boolean("long:robot('snake'):position() == given:robot('snake'):position()"));
}

TEST_CASE("run and step advance time by whole ticks", "[wrap_simulation]") {
    LuaFixture lua;
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 3 }
        world = gaitlab.world()
        world:add(robot)
        sim = gaitlab.simulation{ world = world, seed = 7, solver_iterations = 20 }
    )");
    CHECK(lua.number("sim.time") == 0);
    CHECK(lua.integer("sim.ticks") == 0);
    CHECK(lua.number("sim.dt") == 0.001);
    CHECK(lua.integer("sim.control_every") == 30);
    CHECK(lua.integer("sim.seed") == 7);
    CHECK(lua.integer("sim.solver_iterations") == 20);
    CHECK(lua.string("sim.solver") == "block_nncg");
    lua.run("other = gaitlab.simulation{ world = world, solver = 'pgs' }");
    CHECK(lua.string("other.solver") == "pgs");
    CHECK(lua.integer("sim.newton_steps") == 0);
    lua.run("newton = gaitlab.simulation{ world = world, newton_steps = 4 }");
    CHECK(lua.integer("newton.newton_steps") == 4);
    CHECK(lua.error_of("newton.newton_steps = 2").find("newton_steps") != std::string::npos);
    lua.run("sim:run(1.5)");
    CHECK(lua.integer("sim.ticks") == 1500);
    CHECK(lua.number("sim.time") == Approx(1.5).margin(1e-12));
    lua.run("sim:step(10)");
    CHECK(lua.integer("sim.ticks") == 1510);
    CHECK(lua.number("sim.time") == Approx(1.51).margin(1e-12));
    lua.run("sim:step()");
    CHECK(lua.integer("sim.ticks") == 1511);
    lua.run("sim:run(0)");
    CHECK(lua.integer("sim.ticks") == 1511);
    lua.run("sim:reset()");
    CHECK(lua.integer("sim.ticks") == 0);
    CHECK(lua.number("sim.time") == 0);
    CHECK(lua.string("tostring(sim)") == "gaitlab.Simulation (t = 0.0 s, robots: 1)");

    const std::string run = "test:1: bad argument #1 to 'run' (";
    CHECK(lua.error_of("sim:run(-1)") == run + "non-negative number of seconds expected)");
    CHECK(lua.error_of("sim:run(0/0)") == run + "non-negative number of seconds expected)");
    CHECK(lua.error_of("sim:run('long')") == run + "number expected, got string)");
    CHECK(lua.error_of("sim:step(-1)") ==
          "test:1: bad argument #1 to 'step' (non-negative number of ticks expected)");
    CHECK(lua.error_of("sim:step(1.5)") ==
          "test:1: bad argument #1 to 'step' (number has no integer representation)");
}

TEST_CASE("reset replays the same trajectory", "[wrap_simulation]") {
    LuaFixture lua;
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 4 }
        world = gaitlab.world()
        world:add(robot)
        robot:group("all"):drive(gaitlab.controllers.sine{})
        sim = gaitlab.simulation{ world = world }
        sim:run(1)
        first = robot:position()
        sim:reset()
        start = robot:position()
        sim:run(1)
        second = robot:position()
    )");
    CHECK(lua.boolean("first == second"));
    CHECK(lua.number("(first - start):norm()") > 1e-3);
}

TEST_CASE("sim:objects reports the dynamic objects of the world", "[wrap_simulation]") {
    LuaFixture lua;
    lua.run(R"(
        w = gaitlab.world{ floor = false }
        w:box{ size = { 0.1, 0.1, 0.1 } }                                   -- static: not listed
        w:box{ size = { 0.1, 0.1, 0.1 }, mass = 1, position = { 1, 0, 1 } }
        w:cylinder{ mass = 2, position = { 2, 0, 1 } }
        sim = gaitlab.simulation{ world = w }
        before = sim:objects()
        sim:run(0.5)
        after = sim:objects()
    )");
    CHECK(lua.integer("#before") == 2);
    CHECK(lua.string("before[1].object") == "box 2");
    CHECK(lua.string("before[2].object") == "cylinder 1");
    CHECK(lua.number("before[2].position.x") == 2);
    CHECK(lua.number("before[1].orientation.w") == 1);
    // no floor: both fall freely, 9.81 · 0.5² / 2 m
    CHECK(lua.number("before[1].position.z - after[1].position.z") == Approx(1.226).margin(0.01));
    CHECK(lua.number("after[2].velocity.z") == Approx(-4.905).margin(0.01));
}

TEST_CASE("a Lua controller may drive new groups from its step but not step its simulation",
          "[wrap_simulation][reentrancy]") {
    LuaFixture lua;
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 8 }
        world = gaitlab.world()
        world:add(robot)
        added = {}
        Grower = gaitlab.controller{ name = "grower", step = function(self)
          if #added < 30 then
            local s = gaitlab.controllers.sine{ amplitude = 10 }
            added[#added + 1] = s
            -- a group of its own each time: the joints of the bits of #added
            local joints = {}
            for j = 1, 7 do
              if (#added >> (j - 1)) & 1 == 1 then joints[#joints + 1] = j end
            end
            robot:group(joints):drive(s)
          end
          for m = 1, self.joints do self:set_angle(m, 0) end
        end }
        robot:group("all"):drive(Grower())
        sim = gaitlab.simulation{ world = world }
        sim:run(1)
    )");
    CHECK(lua.integer("#added") == 30);
    CHECK(lua.integer("sim.ticks") == 1000);
    // the first group added stepped from the control tick after the one that added it
    CHECK(lua.number("added[1]:values().time[1]") == Approx(33 * 0.03));

    // sensors attached from a step read from then on, and the step sees them at once
    lua.run(R"(
        robot2 = gaitlab.robot.chain{ name = "worm", modules = 3 }
        world2 = gaitlab.world()
        world2:add(robot2)
        seen = {}
        Watcher = gaitlab.controller{ name = "watcher", step = function(self)
          local n = #seen + 1
          if n <= 20 then
            robot2:sensor{ kind = "imu", module = 1 + n % 3, name = "imu_" .. n }
            seen[n] = self:sensor("imu_" .. n, "qw")
          end
          for m = 1, self.joints do self:set_angle(m, 0) end
        end }
        robot2:group("all"):drive(Watcher())
        sim2 = gaitlab.simulation{ world = world2 }
        sim2:run(1)
    )");
    CHECK(lua.integer("#robot2:sensors()") == 20);
    CHECK(lua.number("seen[20]") == Approx(1).margin(1e-3));
    CHECK(lua.number("robot2:sensor('imu_20'):read().qw") == Approx(1).margin(1e-3));

    for (const char* call : {"sim:run(1)", "sim:step(5)", "sim:reset()"}) {
        LuaFixture inner;
        inner.run(std::string(R"(
            robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
            world = gaitlab.world()
            world:add(robot)
            Nested = gaitlab.controller{ name = "nested", step = function(self)
              )") +
                  call + R"(
            end }
            robot:group("all"):drive(Nested())
            sim = gaitlab.simulation{ world = world }
        )");
        const std::string verb = std::string(call).substr(4, std::string(call).find('(') - 4);
        CHECK(inner.error_of("sim:run(1)") ==
              "test:6: cannot step the simulation from inside its own tick (" + verb +
                  " called from a controller's step: step, run, reset and clone belong between "
                  "ticks)");
        CHECK(inner.integer("sim.ticks") == 0);
    }
}

TEST_CASE("a Lua controller setting a non-finite angle fails", "[wrap_simulation][divergence]") {
    for (const char* value : {"0/0", "1/0", "-math.huge"}) {
        LuaFixture lua;
        lua.run(std::string(R"(
            robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
            world = gaitlab.world()
            world:add(robot)
            Bad = gaitlab.controller{ name = "bad", step = function(self)
              self:set_angle(2, )") +
                value + R"()
            end }
            robot:group("all"):drive(Bad())
            sim = gaitlab.simulation{ world = world }
        )");
        CHECK(lua.error_of("sim:run(1)") ==
              "test:6: bad argument #2 to 'set_angle' (finite number of degrees expected)");
        CHECK(lua.boolean("robot:joints()[2].target == robot:joints()[2].target"));
    }
}

TEST_CASE("counts and run lengths never wrap into other numbers", "[wrap_simulation][limits]") {
    LuaFixture lua;
    lua.run(R"(
        w = gaitlab.world()
        w:add(gaitlab.robot.chain{ modules = 2 })
    )");
    const std::string bad = "test:1: bad argument #1 to 'simulation' (";
    // 2^32 + 30 used to become 30
    CHECK(lua.error_of("gaitlab.simulation{ world = w, control_every = 2^32 + 30 }") ==
          bad + "control_every must be in [1, 1000000] (got 4294967326))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, solver_iterations = 2^32 + 20 }") ==
          bad + "solver_iterations must be in [1, 10000] (got 4294967316))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, record = { record_every = 4294967297 } }") ==
          bad + "field 'record': record_every must be in [1, 1000000] (got 4294967297))");
    lua.run("sim = gaitlab.simulation{ world = w }");
    CHECK(lua.error_of("sim:run(1e17)") ==
          "test:1: bad argument #1 to 'run' (run time must be in [0, 9.0072e+12] s at dt = 0.001 "
          "s (got 1e+17 s))");
    CHECK(lua.error_of("sim:step(2^62)") ==
          "test:1: bad argument #1 to 'step' (ticks must be in [0, 9007199254740992] (got "
          "4611686018427387904))");
    CHECK(lua.integer("sim.ticks") == 0);
    lua.run("sim:step(2^4)");  // a float with an integer value is a count
    CHECK(lua.integer("sim.ticks") == 16);

    const std::string chain = "test:1: bad argument #1 to 'chain' (";
    CHECK(lua.error_of("gaitlab.robot.chain{ modules = 2^32 + 8 }") ==
          chain + "modules must be at most 1000 (got 4294967304))");
    CHECK(lua.error_of("gaitlab.robot.chain{ modules = -2^40 }") ==
          chain + "modules must be at least 1 (got -1099511627776))");
    CHECK(lua.error_of("w:stairs{ steps = 2^32 + 3 }") ==
          "test:1: bad argument #1 to 'stairs' (stairs 1 steps must be in [1, 1000] (got "
          "4294967299))");
    CHECK(lua.error_of("w:pipe{ sides = 2^32 + 8 }") ==
          "test:1: bad argument #1 to 'pipe' (pipe 1 sides must be in [3, 256] (got "
          "4294967304))");
    CHECK(lua.error_of("w:rubble{ count = 2^40 }") ==
          "test:1: bad argument #1 to 'rubble' (rubble 1 count must be in [0, 100000] (got "
          "1099511627776))");
}

TEST_CASE("a robot passing through itself is reported while it runs, once",
          "[wrap_simulation][warnings]") {
    LuaFixture lua;
    std::vector<std::string> reports;
    lua.host.set_reporter([&](const std::string& m) { reports.push_back(m); });
    // floating, every joint bent to 90 deg: the 6-module chain curls its tail into its head
    lua.run(R"(
        function folding(self_collision)
          local robot = gaitlab.robot.chain{ name = "snake", modules = 6,
                                             connection = "pitch-pitch",
                                             self_collision = self_collision }
          local world = gaitlab.world{ gravity = { 0, 0, 0 }, floor = false }
          world:add(robot)
          robot:group("all"):drive(gaitlab.controllers.sine{ amplitude = 0, offset = 90 })
          return gaitlab.simulation{ world = world, record = false }
        end
        sim = folding(false)
        sim:run(0.1)
    )");
    CHECK(reports.empty());
    lua.run("sim:run(2)");
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].rfind("warning: robot 'snake' passes through itself at t = 0.", 0) == 0);
    CHECK(lua.integer("#sim.warnings") == 1);
    CHECK(lua.boolean("('warning: ' .. sim.warnings[1]) == [[" + reports[0] + "]]"));
    lua.run("sim:run(2)");
    CHECK(reports.size() == 1);
    // with self_collision its bodies collide: nothing to report
    lua.run("colliding = folding(true) colliding:run(2)");
    CHECK(reports.size() == 1);
    CHECK(lua.integer("#colliding.warnings") == 0);
}

TEST_CASE("sim:check_accuracy runs the world again at finer settings and warns naming them",
          "[wrap_simulation][accuracy]") {
    LuaFixture lua;
    std::vector<std::string> reports;
    lua.host.set_reporter([&](const std::string& m) { reports.push_back(m); });
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-pitch" }
        world = gaitlab.world{ floor = { friction = 0.8 } }
        world:add(robot)
        robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5,
                                                             phase = 120 })
        fine = gaitlab.simulation{ world = world, control_every = 10, record = false }
        fine:run(0.5)
        r = fine:check_accuracy{ seconds = 6, cycle = 2 }
    )");
    // the defaults: quiet, and the check ran the world from time 0, not this simulation
    CHECK(reports.empty());
    CHECK(lua.number("fine.time") == Approx(0.5));
    CHECK(lua.boolean("robot:displacement() == fine:robot('snake'):displacement()"));
    CHECK(lua.number("r.seconds") == 6);
    CHECK(lua.number("r.cycle") == 2);
    CHECK(lua.number("r.settle") == 0);
    CHECK(lua.number("r.settings.given.dt") == 0.001);
    CHECK(lua.number("r.settings.dt.dt") == 0.00025);
    CHECK(lua.integer("r.settings.dt.control_every") == 40);
    CHECK(lua.integer("r.settings.iterations.solver_iterations") == 80);
    CHECK(lua.integer("#r.robots") == 1);
    CHECK(lua.string("r.robots[1].name") == "snake");
    CHECK(lua.number("r.robots[1].given.path") > 0.15);
    CHECK(lua.number("r.robots[1].given.x") < -0.15);
    CHECK(std::abs(lua.number("r.robots[1].dt_off")) < 1);
    CHECK(std::abs(lua.number("r.robots[1].iterations_off")) < 1);
    CHECK(lua.integer("#r.warnings") == 0);

    // pgs with 2 iterations: a warning for each setting, reported once and returned
    lua.run(R"(
        coarse = gaitlab.simulation{ world = world, control_every = 10, solver = "pgs",
                                     solver_iterations = 2, record = false }
    )");
    REQUIRE(reports.size() == 1);  // the static warning: below 15 iterations
    CHECK(reports[0].rfind("warning: solver_iterations = 2 is below 15", 0) == 0);
    lua.run("r = coarse:check_accuracy{ seconds = 6, cycle = 2 }");
    REQUIRE(reports.size() == 3);
    CHECK(reports[1].rfind("warning: dt = 1 ms: robot 'snake' moves ", 0) == 0);
    CHECK(reports[2].rfind("warning: solver_iterations = 2: robot 'snake' moves ", 0) == 0);
    CHECK(lua.integer("#r.warnings") == 2);
    CHECK(
        lua.boolean("('warning: ' .. r.warnings[2]) == " + std::string("[[") + reports[2] + "]]"));

    // bad arguments, named
    const std::string bad = "test:1: bad argument #1 to 'check_accuracy' (";
    CHECK(lua.error_of("fine:check_accuracy{ second = 6 }") ==
          bad + "unknown key 'second'; did you mean 'seconds'?)");
    CHECK(lua.error_of("fine:check_accuracy{ seconds = 0 }") ==
          bad + "field 'seconds': a positive number of seconds expected)");
    CHECK(lua.error_of("fine:check_accuracy{ seconds = 0/0 }") ==
          bad + "field 'seconds': a positive number of seconds expected)");
    CHECK(lua.error_of("fine:check_accuracy{ seconds = 6, settle = 6 }") ==
          bad + "field 'settle': seconds in [0, seconds) = [0, 6) expected)");
    CHECK(lua.error_of("fine:check_accuracy{ seconds = 6, settle = 2, cycle = 5 }") ==
          bad +
              "field 'cycle': the gait's cycle in seconds expected, in [dt, seconds - settle] "
              "= [0.001, 4])");
    CHECK(lua.error_of("fine:check_accuracy{ seconds = 1e300 }")
              .rfind(bad + "field 'seconds': seconds must be in [0, ", 0) == 0);
    CHECK(lua.error_of("fine:check_accuracy(6)") == bad + "table expected, got number)");
}
