// sim:clone(), sim:robot(name), robot:controllers() and several simulations from one world
// (scripting/src/wrap_simulation.cpp, lua_controller.cpp).
#include <catch2/catch.hpp>

#include <cmath>

#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;

namespace {

// a snake driven by a built-in sine on its pitch joints and a Lua controller with state of
// its own (a clock, a history table shared twice and cyclic) on its yaw joints; `state(sim)`
// gives every body's pose and velocity, hexadecimal, so equal strings are equal bits
const char* kSetUp = R"(
    Wave = gaitlab.controller{
      name = "wave", params = { amplitude = { 20, min = 0, max = 60 } },
      values = { "angle" },
      step = function(self, dt)
        self.t = (self.t or 0) + dt
        self.log = self.log or { count = 0 }
        self.log.count = self.log.count + 1
        self.log.self = self.log
        self.same = self.log
        for m = 1, self.joints do
          -- the clock counted in the shared table: a copy sharing it with the original would
          -- count twice as fast
          self.angle[m] = self.amplitude * math.sin(2 * math.pi * 0.6 * self.same.count * dt + m)
          self:set_angle(m, self.angle[m])
        end
      end,
    }
    robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw" }
    sine = gaitlab.controllers.sine{ amplitude = 40 }
    wave = Wave{}
    robot:group("pitch"):drive(sine)
    robot:group("yaw"):drive(wave)
    world = gaitlab.world()
    world:add(robot)
    function state(sim)
      local out = { string.format("%a %d", sim.time, sim.ticks) }
      for _, b in ipairs(sim:robot("snake"):bodies()) do
        for _, v in ipairs({ b.position.x, b.position.y, b.position.z, b.velocity.x,
                             b.velocity.y, b.velocity.z, b.orientation.w, b.orientation.x,
                             b.orientation.y, b.orientation.z }) do
          out[#out + 1] = string.format("%a", v)
        end
      end
      return table.concat(out, " ")
    end
)";

}  // namespace

TEST_CASE("sim:clone() mid-gait follows the original bit for bit", "[clone]") {
    LuaFixture lua;
    lua.run(kSetUp);
    lua.run(R"(
        sim = gaitlab.simulation{ world = world }
        sim:run(1.3)
        copy = sim:clone()
        same_at_start = state(copy) == state(sim)
        sim:run(2)
        copy:run(2)
    )");
    CHECK(lua.boolean("same_at_start"));
    CHECK(lua.boolean("state(copy) == state(sim)"));
    CHECK(lua.number("copy.time") == Approx(3.3));
    CHECK(lua.boolean("copy ~= sim"));
    // the snake crawled: the comparison is of a gait, not of a robot at rest
    CHECK(lua.number("sim:robot('snake'):displacement():norm()") > 0.02);
    // the Lua controller's copy kept its state: its own clock and table, shared and cyclic
    // as in the original
    lua.run(R"(
        c = copy:robot("snake"):controllers()
        o = sim:robot("snake"):controllers()
    )");
    CHECK(lua.integer("#c") == 2);
    CHECK(lua.string("c[1].name") == "sine");
    CHECK(lua.string("c[2].name") == "wave");
    CHECK(lua.boolean("c[1] ~= o[1]"));
    CHECK(lua.boolean("c[2]:values().angle[3] == o[2]:values().angle[3]"));
    CHECK(lua.boolean("c[2]:values().angle[3] ~= 0"));
}

TEST_CASE("sim:clone{ dt =, ... } goes on from the same state at other settings", "[clone]") {
    LuaFixture lua;
    lua.run(kSetUp);
    lua.run(R"(
        sim = gaitlab.simulation{ world = world, control_every = 10 }
        sim:run(1.3)
        fine = sim:clone{ dt = sim.dt / 4, control_every = 40, solver_iterations = 80 }
        same = sim:clone{ solver_iterations = sim.solver_iterations }
        twin = sim:clone()
        same_at_start = state(fine):gsub("^%S+ %d+", "") == state(sim):gsub("^%S+ %d+", "")
        for _, s in ipairs({ sim, fine, same, twin }) do s:run(1) end
    )");
    CHECK(lua.boolean("same_at_start"));
    CHECK(lua.number("fine.dt") == 0.00025);
    CHECK(lua.integer("fine.control_every") == 40);
    CHECK(lua.integer("fine.solver_iterations") == 80);
    CHECK(lua.number("fine.time") == Approx(2.3));
    CHECK(lua.integer("fine.ticks") == 4 * lua.integer("sim.ticks"));
    // the settings act: another trajectory, close to the original's
    CHECK_FALSE(lua.boolean("state(fine) == state(sim)"));
    CHECK(lua.number("(fine:robot('snake'):position() - sim:robot('snake'):position()):norm()") <
          0.01);
    // the settings given are the original's: clone()'s copy, bit for bit
    CHECK(lua.boolean("state(same) == state(twin)"));
    CHECK(lua.boolean("state(same) == state(sim)"));
    // settings that cannot reach the accuracy are warned of, as a new simulation's
    lua.run("low = sim:clone{ solver_iterations = 3 }");
    CHECK(
        lua.boolean("low.warnings[#low.warnings]:find('solver_iterations = 3 is below 7', 1, "
                    "true) ~= nil"));
    // and give way to the copy's own: a copy of that one at 20 iterations has none of them
    lua.run("back = low:clone{ solver_iterations = 20 }");
    CHECK(lua.integer("#back.warnings") == lua.integer("#sim.warnings"));
    SECTION("bad settings") {
        CHECK(lua.error_of("sim:clone{ dt = sim.dt / 2 }") ==
              "test:1: cannot copy the simulation at dt = 0.0005 s, control_every = 10: the "
              "controllers step every 0.01 s and a copy keeps that (dt x control_every = 0.005 "
              "s; at dt = 0.0005 s, control_every = 20)");
        CHECK(lua.error_of("sim:clone{ solver = 'gs' }") ==
              "test:1: bad argument #1 to 'clone' (field 'solver': 'pgs' or 'block_nncg' "
              "expected, got 'gs')");
        CHECK(lua.error_of("sim:clone{ solver_iterations = 2^32 + 20 }") ==
              "test:1: bad argument #1 to 'clone' (solver_iterations must be in [1, 10000] "
              "(got 4294967316))");
        CHECK(lua.error_of("sim:clone{ dt = 'fine' }").find("'dt'") != std::string::npos);
        // the original runs on
        lua.run("sim:run(0.1)");
        CHECK(lua.number("sim.time") == Approx(2.4));
    }
}

TEST_CASE("a clone on a compliant floor follows the original bit for bit", "[clone]") {
    LuaFixture lua;
    lua.run(kSetUp);
    lua.run(R"(
        function make(floor)
          local w = gaitlab.world{ floor = floor }
          local r = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw" }
          r:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40 })
          w:add(r)
          return gaitlab.simulation{ world = w }
        end
        sim = make({ stiffness = 1e4, damping = 20 })
        rigid = make({})
        sim:run(1.3)
        rigid:run(1.3)
        copy = sim:clone()
        sim:run(2)
        copy:run(2)
        rigid:run(2)
    )");
    CHECK(lua.boolean("state(copy) == state(sim)"));
    CHECK(lua.number("sim:robot('snake'):displacement():norm()") > 0.02);
    // the clone's floor is the compliant one: on the rigid floor the same gait gives other bits
    CHECK_FALSE(lua.boolean("state(copy) == state(rigid)"));
}

TEST_CASE("a clone's parameters are its own", "[clone]") {
    LuaFixture lua;
    lua.run(kSetUp);
    lua.run(R"(
        sim = gaitlab.simulation{ world = world }
        sim:run(1.3)
        changed = sim:clone()
        untouched = sim:clone()
        changed:robot("snake"):controllers()[1].amplitude = 20
        changed:robot("snake"):controllers()[2].amplitude = 5
        sim:run(1)
        changed:run(1)
        untouched:run(1)
    )");
    CHECK(lua.number("sine.amplitude") == 40);
    CHECK(lua.number("wave.amplitude") == 20);
    CHECK(lua.number("untouched:robot('snake'):controllers()[1].amplitude") == 40);
    CHECK(lua.boolean("state(untouched) == state(sim)"));
    CHECK(lua.boolean("state(changed) ~= state(sim)"));
    // the world's handles still act on the original
    lua.run("sine.frequency = 1");
    CHECK(lua.number("untouched:robot('snake'):controllers()[1].frequency") == 0.5);
    CHECK(lua.boolean("sim:robot('snake') ~= nil"));
    // a copy lives on when its original is gone
    lua.run(R"(
        sim = nil
        collectgarbage()
        untouched:run(0.5)
    )");
    CHECK(lua.number("untouched.time") == Approx(2.8));
}

TEST_CASE("one world builds several simulations", "[clone]") {
    LuaFixture lua;
    lua.run(kSetUp);
    // was: "controller 'sine' already drives a group"
    lua.run(R"(
        a = gaitlab.simulation{ world = world }
        a:run(0.5)
        sine.amplitude = 30
        b = gaitlab.simulation{ world = world }
        c = gaitlab.simulation{ world = world }
    )");
    // the first drives with the world's controllers; later ones with fresh copies, parameters
    // as they were when they were built
    CHECK(lua.number("a:robot('snake'):controllers()[1].amplitude") == 30);
    CHECK(lua.number("b:robot('snake'):controllers()[1].amplitude") == 30);
    lua.run("sine.amplitude = 35");
    CHECK(lua.number("a:robot('snake'):controllers()[1].amplitude") == 35);
    CHECK(lua.number("b:robot('snake'):controllers()[1].amplitude") == 30);
    CHECK(lua.number("c:robot('snake'):controllers()[1].amplitude") == 30);
    CHECK(lua.number("b.time") == 0);
    lua.run(R"(
        b:run(1)
        c:run(1)
    )");
    CHECK(lua.boolean("state(b) == state(c)"));
    CHECK(lua.number("b:robot('snake'):displacement():norm()") > 0.005);
    // the world's robot handle reads the newest simulation
    CHECK(lua.boolean("robot:position() == c:robot('snake'):position()"));
}

TEST_CASE("handles after reset, in a clone and in later simulations of one world",
          "[clone][handles]") {
    LuaFixture lua;
    lua.run(kSetUp);
    lua.run(R"(
        eye = robot:sensor{ kind = "imu", module = 3 }
        sim = gaitlab.simulation{ world = world, record = false }
        sim:run(0.2)
        sim:reset()
        -- the ones of this simulation, as table keys
        mine = { [robot] = "robot", [sine] = "sine", [eye] = "eye" }
    )");
    // a reset keeps every robot, controller and sensor: the same handles
    CHECK(lua.boolean("rawequal(sim:robot('snake'), robot)"));
    CHECK(lua.boolean("sim:robot('snake'):controllers()[1] == sine"));
    CHECK(lua.boolean("sim:robot('snake'):controllers()[2] == wave"));
    CHECK(lua.boolean("sim:robot('snake'):sensor('imu3') == eye"));
    CHECK(lua.string("mine[sim:robot('snake')]") == "robot");

    // a clone's robot, controllers and sensors are its own: other handles, each one the same
    // from call to call
    lua.run(R"(
        copy = sim:clone()
        twin = copy:robot("snake")
    )");
    CHECK(lua.boolean("twin ~= robot and mine[twin] == nil"));
    CHECK(lua.boolean("rawequal(copy:robot('snake'), twin)"));
    CHECK(lua.boolean("twin:controllers()[1] ~= sine and mine[twin:controllers()[1]] == nil"));
    CHECK(lua.boolean("rawequal(twin:controllers()[1], copy:robot('snake'):controllers()[1])"));
    CHECK(lua.boolean("twin:sensor('imu3') ~= eye"));
    CHECK(lua.boolean("rawequal(twin:sensor('imu3'), copy:robot('snake'):sensors()[1])"));
    CHECK(lua.boolean("twin:group('pitch') ~= robot:group('pitch')"));
    CHECK(lua.boolean("copy:clone():robot('snake') ~= twin"));
    // comparing across them raises nothing
    CHECK(lua.boolean("twin ~= copy and copy ~= sim and sim == sim and twin ~= eye"));

    // a later simulation of the world is driven by copies of the controllers, and the world's
    // robot handle is its robot; the first simulation's robot becomes a robot of its own, with
    // the controllers it had; each of them keeps its handle from then on
    lua.run(R"(
        later = gaitlab.simulation{ world = world, record = false }
        first = sim:robot("snake")
        second = later:robot("snake")
    )");
    CHECK(lua.boolean("first ~= robot and rawequal(sim:robot('snake'), first)"));
    CHECK(lua.boolean("rawequal(second, robot) and second ~= first"));
    CHECK(lua.boolean("rawequal(later:robot('snake'), second)"));
    CHECK(lua.boolean("first:controllers()[1] == sine"));
    CHECK(lua.boolean("first:sensor('imu3') ~= eye and mine[first] == nil"));
    CHECK(lua.boolean("second:controllers()[1] ~= sine"));
    CHECK(lua.boolean("rawequal(second:controllers()[1], later:robot('snake'):controllers()[1])"));
    CHECK(lua.boolean("rawequal(second:sensor('imu3'), eye)"));
}

TEST_CASE("the world's robot handle is the robot of the newest simulation of its world",
          "[clone][handles]") {
    LuaFixture lua;
    lua.run(kSetUp);
    // two simulations of one world, each with a clone made at 1 s: the clone goes on as its
    // original would without what the script changes afterwards
    lua.run(R"(
        eye = robot:sensor{ kind = "imu", module = 3 }
        first = gaitlab.simulation{ world = world, record = false }
        second = gaitlab.simulation{ world = world, record = false }
        first:run(1)
        second:run(1)
        first_as_was = first:clone()
        second_as_was = second:clone()
        function travel(sim) return sim:robot("snake"):displacement():norm() end
    )");
    // built alike, they moved alike
    CHECK(lua.boolean("state(first) == state(second)"));

    // identity: the world's handle is the newest's robot; the older one's is another
    CHECK(lua.boolean("rawequal(second:robot('snake'), robot)"));
    CHECK(lua.boolean("first:robot('snake') ~= robot"));
    CHECK(lua.boolean("rawequal(first:robot('snake'), first:robot('snake'))"));
    // its controllers: the newest's copies; the first keeps the ones it was given
    CHECK(lua.boolean("robot:controllers()[1] == second:robot('snake'):controllers()[1]"));
    CHECK(lua.boolean("robot:controllers()[1] ~= sine and robot:controllers()[2] ~= wave"));
    CHECK(lua.boolean("first:robot('snake'):controllers()[1] == sine"));
    CHECK(lua.boolean("first:robot('snake'):controllers()[2] == wave"));

    // parameters written through the world's handle change the newest's motion, not the older's
    lua.run(R"(
        robot:controllers()[1].amplitude = 15
        robot:controllers()[2].amplitude = 5
        for _, s in ipairs({ first, second, first_as_was, second_as_was }) do s:run(2) end
    )");
    CHECK(lua.number("first:robot('snake'):controllers()[1].amplitude") == 40);
    CHECK(lua.number("second:robot('snake'):controllers()[1].amplitude") == 15);
    CHECK(lua.number("sine.amplitude") == 40);
    CHECK(lua.number("wave.amplitude") == 20);
    CHECK(lua.boolean("state(first) == state(first_as_was)"));
    CHECK(lua.boolean("state(second) ~= state(second_as_was)"));
    CHECK(std::abs(lua.number("travel(second) - travel(second_as_was)")) > 0.01);
    CHECK(lua.number("travel(first)") == lua.number("travel(first_as_was)"));

    // state read through the world's handle is the newest's: centre of mass, joints, bodies,
    // sensors (and not the first's, which moves otherwise now)
    CHECK(lua.boolean("robot:position() == second:robot('snake'):position()"));
    CHECK(lua.boolean("robot:position() ~= first:robot('snake'):position()"));
    CHECK(lua.number("robot:joints()[3].angle") ==
          lua.number("second:robot('snake'):joints()[3].angle"));
    CHECK(lua.number("robot:bodies()[2].position.x") ==
          lua.number("second:robot('snake'):bodies()[2].position.x"));
    CHECK(lua.number("robot:displacement().x") ==
          lua.number("second:robot('snake'):displacement().x"));
    CHECK(lua.number("eye:read().pitch") ==
          lua.number("second:robot('snake'):sensor('imu3'):read().pitch"));
    CHECK(lua.boolean("eye:read().pitch ~= first:robot('snake'):sensor('imu3'):read().pitch"));

    // the older simulation's handle reads and drives the older one
    lua.run(R"(
        old = first:robot("snake")
        first_as_was = first:clone()
        second_as_was = second:clone()
        old:controllers()[1].amplitude = 25
        for _, s in ipairs({ first, second, first_as_was, second_as_was }) do s:run(1) end
    )");
    CHECK(lua.boolean("old:position() == first:robot('snake'):position()"));
    CHECK(lua.boolean("old:position() ~= robot:position()"));
    CHECK(lua.boolean("state(first) ~= state(first_as_was)"));
    CHECK(lua.boolean("state(second) == state(second_as_was)"));
    CHECK(lua.number("robot:controllers()[1].amplitude") == 15);

    // groups, actuations and sensor switches through the world's handle: the newest's
    lua.run(R"(
        hold = robot:group{ 1 }:drive(gaitlab.controllers.offset{ angle = 5 })
        made = robot:actuate(gaitlab.actuation{ groups = {
          { joints = { 2 }, controller = { builtin = "offset", params = { angle = 3 } } } } })
        old:group{ 4 }:drive(gaitlab.controllers.offset{ angle = 7 })
        eye:off()
    )");
    CHECK(lua.integer("#second:robot('snake'):controllers()") == 4);
    CHECK(lua.boolean("second:robot('snake'):controllers()[3] == hold"));
    CHECK(lua.boolean("second:robot('snake'):controllers()[4] == made[1]"));
    CHECK(lua.integer("#robot:controllers()") == 4);
    CHECK(lua.integer("#first:robot('snake'):controllers()") == 3);
    CHECK(lua.integer("#old:controllers()") == 3);
    CHECK(lua.number("old:controllers()[3].angle") == 7);
    CHECK(lua.boolean("rawequal(first:robot('snake'), old)"));
    CHECK(lua.boolean("eye:read() == nil and not second:robot('snake'):sensor('imu3').enabled"));
    CHECK(lua.boolean("old:sensor('imu3').enabled and old:sensor('imu3'):read() ~= nil"));
    CHECK(lua.boolean("old:sensor('imu3') ~= eye"));

    // a third simulation: built from the world's handle as it stands (the second's controllers,
    // its parameters and groups, the sensor off); the handle moves on to it, and the second's
    // robot becomes one of its own that keeps the second's controllers
    lua.run(R"(
        third = gaitlab.simulation{ world = world, record = false }
        older = second:robot("snake")
    )");
    CHECK(lua.boolean("rawequal(third:robot('snake'), robot)"));
    CHECK(lua.boolean("older ~= robot and older ~= old"));
    CHECK(lua.integer("#third:robot('snake'):controllers()") == 4);
    CHECK(lua.number("third:robot('snake'):controllers()[1].amplitude") == 15);
    CHECK(lua.boolean("third:robot('snake'):controllers()[3] ~= hold"));
    CHECK(lua.boolean("older:controllers()[3] == hold"));
    CHECK(lua.boolean("not third:robot('snake'):sensor('imu3').enabled"));
    CHECK(lua.number("third.time") == 0);
    // after a reset of an older simulation its robot is still its own
    lua.run("first:reset()");
    CHECK(lua.boolean("rawequal(first:robot('snake'), old) and old:controllers()[1] == sine"));
    CHECK(lua.boolean("rawequal(third:robot('snake'), robot)"));
}

TEST_CASE("sim:save of an older simulation of a world saves its own controllers",
          "[clone][handles]") {
    TempDir dir("older_save");
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
        robot:group("all"):drive(gaitlab.controllers.sine{ amplitude = 40 })
        world = gaitlab.world()
        world:add(robot)
        first = gaitlab.simulation{ world = world, record = false }
        second = gaitlab.simulation{ world = world, record = false }
        robot:controllers()[1].amplitude = 15
        first:robot("snake"):controllers()[1].amplitude = 25
        assert(first:save(DIR .. "/first.xml"))
        assert(second:save(DIR .. "/second.xml"))
        a = assert(gaitlab.simulation.load(DIR .. "/first.xml"))
        b = assert(gaitlab.simulation.load(DIR .. "/second.xml"))
    )");
    CHECK(lua.number("a:robot('snake'):controllers()[1].amplitude") == 25);
    CHECK(lua.number("b:robot('snake'):controllers()[1].amplitude") == 15);
}

TEST_CASE("sim:save writes the world as the simulation has it, not as the world is now",
          "[clone][handles]") {
    TempDir dir("save_as_built");
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-yaw" }
        robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30 })
        world = gaitlab.world()
        world:add(robot)
        sim = gaitlab.simulation{ world = world, record = false }
        -- added to the world after the simulation was built: not in it
        world:box{ size = { 0.2, 0.2, 0.2 }, position = { 0.3, 0, 0.1 } }
        world:add(gaitlab.robot.chain{ name = "worm", modules = 3 }, { y = 1 })
        sim:run(2)
        assert(sim:save(DIR .. "/sim.xml"))
        loaded, setup = assert(gaitlab.simulation.load(DIR .. "/sim.xml"))
        loaded:run(2)
    )");
    CHECK(lua.string("tostring(setup.world)") == "gaitlab.World (1 robot, 0 boxes)");
    CHECK(lua.boolean("setup.robots.worm == nil"));
    // the saved simulation moves as the one saved did
    CHECK(lua.number("setup.robots.snake:position().x") == lua.number("robot:position().x"));
}

TEST_CASE("a simulation that fails to be made changes no robot handle and no controller",
          "[clone][handles]") {
    TempDir dir("failed_build");
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-yaw" }
        sine = robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30 })
        world = gaitlab.world()
        world:add(robot)
        -- a series that matches nothing: refused once the simulation is built
        bad = { dir = DIR .. "/bad", series = { "snake.com.xx" } }
    )");
    SECTION("before any simulation: the next one is driven by the script's controller") {
        CHECK_THAT(lua.error_of("gaitlab.simulation{ world = world, record = bad }"),
                   Catch::Contains("no series matches 'snake.com.xx'"));
        lua.run(R"(
            sim = gaitlab.simulation{ world = world, record = false }
            sine.amplitude = 0
            sim:run(2)
        )");
        CHECK(lua.boolean("sim:robot('snake') == robot"));
        CHECK(lua.boolean("robot:controllers()[1] == sine"));
        // the amplitude written through the script's controller stopped the gait
        CHECK(lua.number("robot:displacement():norm()") < 1e-3);
    }
    SECTION("after one: the handle stays the first simulation's robot") {
        lua.run(R"(
            first = gaitlab.simulation{ world = world, record = false }
            first:run(1)
            x = robot:position().x
        )");
        CHECK_THAT(lua.error_of("gaitlab.simulation{ world = world, record = bad }"),
                   Catch::Contains("no series matches 'snake.com.xx'"));
        CHECK(lua.boolean("first:robot('snake') == robot"));
        CHECK(lua.boolean("robot:controllers()[1] == sine"));
        CHECK(lua.number("robot:position().x") == lua.number("x"));
    }
}

TEST_CASE("clone: a Lua controller's tables are copied however deep they nest", "[clone]") {
    // a linked list of 200 000 nodes is as deep as it is long: a copy that recursed once per
    // level ran out of C stack and crashed the process
    LuaFixture lua;
    lua.run(R"(
        Deep = gaitlab.controller{ name = "deep", values = { "length", "step" },
          step = function(self)
            if not self.list then
              local head = { n = 1 }
              local node = head
              for i = 2, 200000 do node.next = { n = i }; node = node.next end
              node.next = head  -- and round again: a cycle 200 000 long
              self.list, self.tail = head, node
            end
            -- the list as the copy sees it: its length round the cycle, and the tail the same
            -- table as the last node; each step moves the head one on
            local n, node = 1, self.list
            while node.next ~= self.list do n = n + 1; node = node.next end
            for m = 1, self.joints do
              self.length[m] = (node == self.tail) and n or -n
              self.step[m] = self.list.n
              self:set_angle(m, 0)
            end
            self.tail, self.list = self.list, self.list.next
          end }
        r = gaitlab.robot.chain{ name = "r", modules = 2 }
        w = gaitlab.world()
        w:add(r)
        r:group("all"):drive(Deep{})
        s = gaitlab.simulation{ world = w, control_every = 1 }
        s:step(3)
        c = s:clone()
        c:step(2)
        mine = c:robot("r"):controllers()[1]:values()
        theirs = s:robot("r"):controllers()[1]:values()
    )");
    CHECK(lua.number("mine.length[1]") == 200000);
    CHECK(lua.number("mine.step[1]") == 5);    // the copy went on from where the original was
    CHECK(lua.number("theirs.step[1]") == 3);  // and the original stayed there
    lua.run("s:step(1) theirs = s:robot('r'):controllers()[1]:values()");
    CHECK(lua.number("theirs.step[1]") == 4);

    // what cannot be copied is still named by its path, however deep
    lua.run(R"(
        Holder = gaitlab.controller{ name = "holder",
          step = function(self)
            if not self.chain then
              local node = {}
              self.chain = node
              for i = 1, 1000 do node.next = {}; node = node.next end
              node[{ "as key" }] = { co = coroutine.create(function() end) }
            end
            for m = 1, self.joints do self:set_angle(m, 0) end
          end }
        r2 = gaitlab.robot.chain{ name = "r2", modules = 2 }
        w2 = gaitlab.world()
        w2:add(r2)
        r2:group("all"):drive(Holder{})
        s2 = gaitlab.simulation{ world = w2 }
        s2:step(1)
    )");
    const std::string message = lua.error_of("s2:clone()");
    CHECK_THAT(message, Catch::StartsWith("test:1: controller 'holder' cannot be copied: "
                                          "self.chain.next.next.next"));
    CHECK_THAT(message, Catch::Contains(".next.next[<table>].co holds a coroutine"));
}

TEST_CASE("clone: bad uses", "[clone]") {
    LuaFixture lua;
    lua.run(kSetUp);
    lua.run("sim = gaitlab.simulation{ world = world }");
    SECTION("unknown robot") {
        CHECK(lua.error_of("sim:robot('snak')") ==
              "test:1: bad argument #1 to 'robot' (the simulation has no robot 'snak'; did you "
              "mean 'snake'? (its robots: snake))");
    }
    SECTION("bad options") {
        CHECK(lua.error_of("sim:clone(3)") ==
              "test:1: bad argument #1 to 'clone' (table expected, got number)");
        CHECK(lua.error_of("sim:clone{ recrd = true }") ==
              "test:1: bad argument #1 to 'clone' (unknown key 'recrd'; did you mean "
              "'record'?)");
    }
    SECTION("from inside a tick") {
        lua.run(R"(
            Cloner = gaitlab.controller{ name = "cloner",
              step = function(self) sim:clone() end }
            other = gaitlab.robot.chain{ name = "other", modules = 2 }
            w2 = gaitlab.world()
            w2:add(other)
            other:group("all"):drive(Cloner{})
            sim = gaitlab.simulation{ world = w2 }
        )");
        CHECK(lua.error_of("sim:run(0.1)") ==
              "test:3: cannot step the simulation from inside its own tick (clone called from a "
              "controller's step: step, run, reset and clone belong between ticks)");
    }
    SECTION("a Lua controller holding what cannot be copied") {
        lua.run(R"(
            sim:run(0.2)
            wave_in_sim = sim:robot("snake"):controllers()[2]
        )");
        // the instance table is reached through the class's step: put a coroutine in it
        lua.run(R"(
            Holder = gaitlab.controller{ name = "holder",
              step = function(self)
                self.plan = self.plan or { steps = { coroutine.create(function() end) } }
                for m = 1, self.joints do self:set_angle(m, 0) end
              end }
            r3 = gaitlab.robot.chain{ name = "r3", modules = 3 }
            w3 = gaitlab.world()
            w3:add(r3)
            r3:group("all"):drive(Holder{})
            s3 = gaitlab.simulation{ world = w3 }
            s3:step(1)
        )");
        CHECK(lua.error_of("s3:clone()") ==
              "test:1: controller 'holder' cannot be copied: self.plan.steps[1] holds a "
              "coroutine (only numbers, strings, booleans, tables and functions without "
              "upvalues can be copied; the copy would share it with the original)");
        // the original runs on
        lua.run("s3:run(0.1)");
        CHECK(lua.integer("s3.ticks") > 1);
        lua.run(R"(
            Closure = gaitlab.controller{ name = "closure",
              step = function(self)
                local n = 0
                self.count = self.count or function() n = n + 1 return n end
                for m = 1, self.joints do self:set_angle(m, 0) end
              end }
            r4 = gaitlab.robot.chain{ name = "r4", modules = 3 }
            w4 = gaitlab.world()
            w4:add(r4)
            r4:group("all"):drive(Closure{})
            s4 = gaitlab.simulation{ world = w4 }
            s4:step(1)
        )");
        CHECK(lua.error_of("s4:clone()") ==
              "test:1: controller 'closure' cannot be copied: self.count holds a function with "
              "upvalues (only numbers, strings, booleans, tables and functions without "
              "upvalues can be copied; the copy would share it with the original)");
    }
    SECTION("a failed simulation clones, failure and all") {
        lua.run(R"(
            Failing = gaitlab.controller{ name = "failing",
              step = function(self) error("broken on purpose") end }
            r5 = gaitlab.robot.chain{ name = "r5", modules = 3 }
            w5 = gaitlab.world()
            w5:add(r5)
            r5:group("all"):drive(Failing{})
            s5 = gaitlab.simulation{ world = w5, on_controller_error = "continue" }
            s5:run(0.2)
            c5 = s5:clone()
        )");
        CHECK(lua.boolean("c5:robot('r5'):controllers()[1].failed"));
        CHECK(lua.string("c5:status().controllers[1].state") == "failed");
    }
}
