// Controllers written in Lua (scripting/src/lua_controller.cpp): same trajectory as the C++
// sine, errors that name their file and line, a balanced Lua stack while the engine steps them.
#include <catch2/catch.hpp>

#include <memory>

#include "gaitlab/simulation.h"
#include "lua_controller.h"
#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::scripting::LuaController;
using gaitlab::scripting::LuaControllerClass;
using gaitlab::scripting::ScriptError;
using gaitlab::test::lua_dir;
using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

// loads a controller class with gaitlab.controller.load, from C++
std::shared_ptr<LuaControllerClass> load_class(lua_State* L, const std::string& path) {
    const int top = lua_gettop(L);
    lua_getglobal(L, "gaitlab");
    lua_getfield(L, -1, "controller");
    lua_getfield(L, -1, "load");
    lua_pushstring(L, path.c_str());
    gaitlab::scripting::protected_call(L, 1, 1);
    void* p = luaL_testudata(L, -1, "gaitlab.ControllerClass");
    REQUIRE(p != nullptr);
    auto cls = *static_cast<std::shared_ptr<LuaControllerClass>*>(p);
    lua_settop(L, top);
    return cls;
}

// a 3-module chain on a floor whose joints are all driven by `controller`
gaitlab::WorldSpec driven_chain(std::shared_ptr<gaitlab::Controller> controller) {
    gaitlab::ChainSpec chain;
    chain.modules = 3;
    gaitlab::WorldSpec world;
    world.robots.push_back({gaitlab::make_chain(chain),
                            gaitlab::Pose{},
                            {gaitlab::Drive{{0, 1, 2}, std::move(controller)}}});
    return world;
}

}  // namespace

TEST_CASE("the Lua my_sine and the C++ sine give the same trajectory", "[lua_controller]") {
    LuaFixture lua;
    lua.run("EXAMPLES = '" GAITLAB_SOURCE_DIR "/examples'");
    lua.run(R"(
        local MySine = gaitlab.controller.load(EXAMPLES .. "/controllers/my_sine.lua")
        local params = { amplitude = 35, frequency = 0.7, phase = 100 }

        -- the centre of mass, then every body's position, at every control tick of 5 s
        local function trajectory(controller)
          local robot = gaitlab.robot.chain{ modules = 8, connection = "pitch-pitch" }
          local world = gaitlab.world{ floor = { friction = 0.8 } }
          world:add(robot)
          robot:group("pitch"):drive(controller)
          local sim = gaitlab.simulation{ world = world, dt = 0.001, control_every = 30 }
          local samples = {}
          while sim.ticks < 5000 do
            sim:step(30)
            local sample = { robot:position() }
            for _, body in ipairs(robot:bodies()) do sample[#sample + 1] = body.position end
            samples[#samples + 1] = sample
          end
          return samples, robot:displacement()
        end

        local lua_run, lua_d = trajectory(MySine(params))
        local cpp_run, cpp_d = trajectory(gaitlab.controllers.sine(params))
        samples, points, max_diff, identical = #lua_run, 0, 0, true
        for k = 1, #lua_run do
          for i = 1, #lua_run[k] do
            local a, b = lua_run[k][i], cpp_run[k][i]
            max_diff = math.max(max_diff, (a - b):norm())
            identical = identical and a == b
            points = points + 1
          end
        end
        moved = lua_d:norm()
        moved_cpp = cpp_d:norm()
    )");
    // 167 control periods of 30 ms; centre of mass + 9 bodies each
    CHECK(lua.integer("samples") == 167);
    CHECK(lua.integer("points") == 167 * 10);
    CHECK(lua.number("max_diff") <= 1e-9);
    // same operations in the same order: they agree bit for bit
    CHECK(lua.boolean("identical"));
    // and the snake did go somewhere, so the comparison means something
    CHECK(lua.number("moved") > 0.02);
    CHECK(lua.number("moved") == lua.number("moved_cpp"));
}

TEST_CASE("a runtime error in step names the controller file and line", "[lua_controller]") {
    LuaFixture lua;
    const std::string file = lua_dir() + "/step_error.lua";
    lua.run("FILE = '" + file + "'");
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        robot:group("all"):drive(gaitlab.controller.load(FILE){})
        sim = gaitlab.simulation{ world = world }
    )");
    const ScriptError e = lua.script_error_of("sim:run(1)");
    CHECK(std::string(e.what()) ==
          file + ":6: attempt to perform arithmetic on a nil value (field 'missing_value')");
    CHECK(e.file() == file);
    CHECK(e.line() == 6);
    CHECK_THAT(e.traceback(), Catch::Contains("step_error.lua:6: in function"));
    CHECK_THAT(e.traceback(), Catch::Contains("test:1: in main chunk"));
    // the failure happened at the first control tick
    CHECK(lua.integer("sim.ticks") <= 1);
}

TEST_CASE("a runtime error in step, called from C++, is a ScriptError", "[lua_controller]") {
    gaitlab::scripting::LuaHost host;
    lua_State* L = host.state();
    const std::string file = lua_dir() + "/step_error.lua";
    auto controller = std::make_shared<LuaController>(L, load_class(L, file));
    gaitlab::Simulation sim(driven_chain(controller));
    REQUIRE(lua_gettop(L) == 0);
    try {
        sim.step(100);
        FAIL("step did not fail");
    } catch (const ScriptError& e) {
        CHECK(std::string(e.what()) ==
              file + ":6: attempt to perform arithmetic on a nil value (field 'missing_value')");
        CHECK(e.file() == file);
        CHECK(e.line() == 6);
        CHECK_THAT(e.traceback(), Catch::Contains("step_error.lua:6: in function"));
    }
    CHECK(lua_gettop(L) == 0);
}

TEST_CASE("stepping Lua controllers from C++ keeps the Lua stack balanced", "[lua_controller]") {
    gaitlab::scripting::LuaHost host;
    lua_State* L = host.state();
    lua_pushinteger(L, 7);  // something the controller must not disturb
    auto controller = std::make_shared<LuaController>(L, load_class(L, lua_dir() + "/counter.lua"));
    gaitlab::Simulation sim(driven_chain(controller));
    CHECK(lua_gettop(L) == 1);
    sim.step(3000);  // 100 control steps
    CHECK(lua_gettop(L) == 1);
    CHECK(lua_tointeger(L, 1) == 7);

    const int steps = controller->find_value("steps");
    const int seen = controller->find_value("seen");
    REQUIRE(steps >= 0);
    REQUIRE(seen >= 0);
    const std::vector<double>& count = controller->values(steps);
    CHECK(lua_gettop(L) == 1);
    REQUIRE(count.size() == 3);
    CHECK(count[0] == Approx(100).margin(1));
    CHECK(count[2] == count[0]);
    // the servos reached the level the controller set (10 deg) and the controller read it back
    CHECK(controller->values(seen)[1] == Approx(10).margin(0.5));
    CHECK(gaitlab::rad_to_deg(sim.joint(0, 1).target) == Approx(10));

    controller->set_param("level", -20);
    sim.step(1500);
    CHECK(lua_gettop(L) == 1);
    CHECK(gaitlab::rad_to_deg(sim.joint(0, 1).target) == Approx(-20));
    sim.reset();
    CHECK(controller->values(steps)[0] == 0);
    CHECK(lua_gettop(L) == 1);
}

TEST_CASE("self:sensor reads the robot's sensors in degrees, nil when off", "[lua_controller]") {
    LuaFixture lua;
    lua.run(R"(
        -- each step copies what it reads into self.seen
        Reader = gaitlab.controller{
          name = "reader",
          step = function(self, dt)
            local j = self:sensor("joint3")
            self.seen = {
              table = j and j.angle, channel = self:sensor("joint3", "angle"),
              angle = self:joint_angle(3), touch = self:sensor("contact1", "contact"),
              imu = self:sensor("imu1"),
            }
            self:set_angle(3, 25)
            seen = self.seen
          end,
        }
        robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
        world = gaitlab.world()
        world:add(robot)
        js = robot:sensor{ kind = "joint", joint = 3 }
        robot:sensor{ kind = "contact", module = 1 }
        imu = robot:sensor{ kind = "imu", module = 1, enabled = false }
        robot:group("all"):drive(Reader{})
        sim = gaitlab.simulation{ world = world }
        sim:run(1)
    )");
    // the joint sensor, read by the controller, is the joint's angle it sees, in degrees; joint
    // 3 lifts the head half only
    CHECK(lua.number("seen.table") == Approx(25).margin(0.5));
    CHECK(lua.number("seen.table") == lua.number("seen.angle"));
    CHECK(lua.number("seen.channel") == lua.number("seen.angle"));
    CHECK(lua.boolean("seen.touch == true"));
    CHECK(lua.boolean("seen.imu == nil"));  // switched off
    lua.run("imu:on() js:off() sim:run(0.1)");
    CHECK(lua.boolean("seen.table == nil and seen.channel == nil"));
    CHECK(lua.number("seen.imu.az") == Approx(9.81).margin(0.05));

    // errors name what exists, in the controller's step
    lua.run(R"(
        Bad = gaitlab.controller{ name = "bad", step = function(self) self:sensor(WHAT, CH) end }
        robot2 = gaitlab.robot.chain{ name = "other", modules = 2 }
        world2 = gaitlab.world()
        world2:add(robot2)
        robot2:sensor{ kind = "imu", module = 2 }
        robot2:group("all"):drive(Bad{})
        sim2 = gaitlab.simulation{ world = world2 }
    )");
    lua.run("WHAT = 'imu3'");
    CHECK(lua.error_of("sim2:step(1)") ==
          "test:2: bad argument #1 to 'sensor' (the controller's robot has no sensor 'imu3'; did "
          "you mean 'imu2'? (its sensors: imu2))");
    lua.run("WHAT = 'imu2' CH = 'pich'");
    lua.run("sim2:reset()");
    CHECK(lua.error_of("sim2:step(1)") ==
          "test:2: bad argument #2 to 'sensor' (imu sensors have no channel 'pich'; did you mean "
          "'pitch'? (channels: roll, pitch, yaw, qw, qx, qy, qz, wx, wy, wz, ax, ay, az))");
    lua.run("WHAT = 42 CH = nil");
    lua.run("sim2:reset()");
    CHECK(lua.error_of("sim2:step(1)") ==
          "test:2: bad argument #1 to 'sensor' (the controller's robot has no sensor '42' (its "
          "sensors: imu2))");
}

TEST_CASE("sensor feedback: the shuttle turns back before the wall", "[lua_controller]") {
    // examples/controllers/shuttle.lua reverses its gait when its range sensor sees a wall
    // closer than `near`; with its sensors off it crawls into the wall
    LuaFixture lua;
    lua.run("EXAMPLES = '" GAITLAB_SOURCE_DIR "/examples'");
    lua.run(R"(
        local Shuttle = gaitlab.controller.load(EXAMPLES .. "/controllers/shuttle.lua")
        function crawl(feedback)
          local robot = gaitlab.robot.chain{ modules = 8 }
          local world = gaitlab.world{ floor = { friction = 0.8 } }
          world:add(robot)
          world:box{ size = {0.05, 1, 0.3}, position = {-0.2, 0, 0.15} }  -- face at -0.175
          robot:sensor{ kind = "range", name = "back", module = 1, half = "tail",
                        direction = {-1, 0, 1}, enabled = feedback }
          robot:sensor{ kind = "range", name = "front", module = 8, direction = {1, 0, 1},
                        enabled = feedback }
          robot:group("all"):drive(Shuttle{ near = 0.1 })
          local sim = gaitlab.simulation{ world = world }
          local start, closest = robot:position().x, math.huge
          for _ = 1, 80 do
            sim:run(0.1)
            closest = math.min(closest, robot:bodies()[1].position.x - 0.018 + 0.175)
          end
          return closest, robot:position().x - start, robot:velocity().x
        end
        with_gap, with_dx = crawl(true)
        without_gap, without_dx = crawl(false)
    )");
    // with feedback it turns back short of the wall and crawls away past its start
    CHECK(lua.number("with_gap") > 0.03);
    CHECK(lua.number("with_dx") > 0.02);
    // without, it reaches the wall and stays there
    CHECK(lua.number("without_gap") < 0.01);
    CHECK(lua.number("without_dx") < -0.1);
}

TEST_CASE("a controller that replaces its value arrays fails with a message", "[lua_controller]") {
    // in step, after a hot reload (on_reload), in a controller a simulation file loads
    for (const char* what : {"nil", "5", "'text'", "print"}) {
        CAPTURE(what);
        TempDir tmp("lua_swap");
        LuaFixture lua;
        lua.run(std::string("WHAT = ") + what + " OUT = '" + (tmp / "run") + "'");
        lua.run(R"(
            C = gaitlab.controller{ name = "swap", values = { "time", "angle" },
              step = function(self, dt)
                self.time[1] = self.time[1] + dt
                if self.time[1] > 0.1 then self.time = WHAT end
              end }
            robot = gaitlab.robot.chain{ modules = 3 }
            world = gaitlab.world()
            world:add(robot)
            ctl = robot:group("pitch"):drive(C{})
            sim = gaitlab.simulation{ world = world, record = { dir = OUT, record_every = 1 } }
        )");
        CHECK(lua.error_of("sim:run(1)") ==
              "test:3: controller 'swap': self.time must stay a table (one number per joint), "
              "got " +
                  lua.string("type(WHAT)"));
        CHECK(lua.boolean("ctl.failed"));
        // the last good values stay readable
        CHECK(lua.number("ctl:values().time[1]") == Approx(0.09));
        CHECK(lua.number("ctl:values().time[2]") == 0);
        lua.run("sim:record(false)");  // the recording closes with every row readable
        lua.run("run = gaitlab.data.open(OUT)");
        CHECK(lua.number("run:get('swap.time[1]').values[#run:get('swap.time[1]').values]") ==
              Approx(0.09));
    }
}

TEST_CASE("a broken value array is reported at the function that broke it", "[lua_controller]") {
    // the definition of step (or on_reload) in the controller file, not gaitlab.controller{
    TempDir tmp("lua_values_line");
    const std::string file = tmp / "y.lua";
    write_text(file, R"(-- y: a controller that breaks its values
-- second comment line

return gaitlab.controller{
  name = "y", values = { "time" },
  params = {},
  step = function(self, dt)
    self.time = nil
  end,
}
)");
    LuaFixture lua;
    lua.run("FILE = '" + file + "'");
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group("all"):drive(gaitlab.controller.load(FILE){})
        sim = gaitlab.simulation{ world = world }
    )");
    const ScriptError e = lua.script_error_of("sim:run(0.1)");
    CHECK(std::string(e.what()) == file +
                                       ":7: controller 'y': self.time must stay a table (one "
                                       "number per joint), got nil");
    CHECK(e.file() == file);
    CHECK(e.line() == 7);
    // a hook that breaks them: its own line
    write_text(file, R"(return gaitlab.controller{ name = "y", values = { "time" },
  step = function(self, dt) end,
  on_reload = function(self)
    self.time = 5
  end })");
    LuaFixture other;
    other.run("FILE = '" + file + "'");
    other.run(R"(
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        robot:group("all"):drive(gaitlab.controller.load(FILE){})
        sim = gaitlab.simulation{ world = world }
        sim:run(0.1)
    )");
    write_text(file, R"(return gaitlab.controller{ name = "y", values = { "time" },
  step = function(self, dt) end,

  on_reload = function(self)
    self.time = 5
  end })");
    other.run("assert(gaitlab.controller.reload())");
    CHECK(other.error_of("sim:run(0.1)") == file +
                                                ":4: controller 'y': self.time must stay a table "
                                                "(one number per joint), got number");
}

TEST_CASE("a reload or a simulation file cannot slip a broken value array past the check",
          "[lua_controller]") {
    TempDir tmp("lua_values");
    LuaFixture lua;
    const std::string file = tmp / "c.lua";
    write_text(file, R"(return gaitlab.controller{ name = "c", values = { "time" },
  step = function(self, dt) self.time[1] = self.time[1] + dt end })");
    lua.run("C = gaitlab.controller.load('" + file + "')");
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group("pitch"):drive(C{})
        sim = gaitlab.simulation{ world = world }
        sim:run(0.1)
    )");
    write_text(file, R"(return gaitlab.controller{ name = "c", values = { "time" },
  step = function(self, dt) self.time[1] = self.time[1] + dt end,
  on_reload = function(self) self.time = 5 end })");
    lua.run("assert(gaitlab.controller.reload())");
    CHECK_THAT(lua.error_of("sim:run(0.1)"),
               Catch::EndsWith("controller 'c': self.time must stay a table (one number per "
                               "joint), got number"));
    // the same controller file loaded by a simulation file
    write_text(file, R"(return gaitlab.controller{ name = "c", values = { "time" },
  step = function(self, dt) self.time = nil end })");
    write_text(tmp / "robot.xml",
               "<gaitlab version=\"1\"><robot name=\"snake\"><chain modules=\"2\"/></robot>"
               "</gaitlab>");
    write_text(tmp / "act.xml",
               "<gaitlab version=\"1\"><actuation><group joints=\"pitch\"><controller "
               "file=\"c.lua\"/></group></actuation></gaitlab>");
    write_text(tmp / "env.xml",
               "<gaitlab version=\"1\"><environment><floor/></environment></gaitlab>");
    write_text(tmp / "sim.xml",
               "<gaitlab version=\"1\"><simulation name=\"s\" duration=\"1\"><environment "
               "file=\"env.xml\"/><robot file=\"robot.xml\" actuation=\"act.xml\"/>"
               "</simulation></gaitlab>");
    LuaFixture other;
    CHECK_THAT(other.error_of("gaitlab.simulation.run_file('" + (tmp / "sim.xml") + "')"),
               Catch::Contains("self.time must stay a table (one number per joint)"));
}

TEST_CASE("a self table kept after its controller is gone reaches nothing", "[lua_controller]") {
    LuaFixture lua;
    lua.run(R"(
        C = gaitlab.controller{ name = "keep", step = function(self, dt) KEPT = self end }
        do
          local robot = gaitlab.robot.chain{ modules = 2 }
          local world = gaitlab.world()
          world:add(robot)
          robot:group("pitch"):drive(C{})
          local sim = gaitlab.simulation{ world = world, record = false }
          sim:step(1)
        end
        collectgarbage() collectgarbage()
    )");
    CHECK(lua.error_of("KEPT:set_angle(1, 10)") ==
          "test:1: this controller is gone (its simulation and handles were removed)");
    CHECK_THAT(lua.error_of("KEPT:joint_angle(1)"), Catch::Contains("this controller is gone"));
    // while it exists but does not step, it says so
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        robot:group("pitch"):drive(C{})
        sim = gaitlab.simulation{ world = world, record = false }
        sim:step(1)
    )");
    CHECK(lua.error_of("KEPT:set_angle(1, 10)") ==
          "test:1: set_angle can only be called while the controller steps");
}

TEST_CASE("a controller rebinds safely after the collector took its old methods",
          "[lua_controller]") {
    // sim:reset binds every controller again, while an eager collector runs; a step that
    // drops its self table's metatable leaves the old methods to the collector
    LuaFixture lua;
    lua.run(R"(
        collectgarbage("incremental", 1, 1000)
        Wave = gaitlab.controller{ name = "wave", values = { "time" }, step = function(self) end }
        Drop = gaitlab.controller{ name = "drop", step = function(self) setmetatable(self, nil) end }
        robot = gaitlab.robot.chain{ modules = 3 }
        world = gaitlab.world{}
        world:add(robot)
        robot:group{ 1, 2 }:drive(Wave())
        robot:group{ 3 }:drive(Drop())
        sim = gaitlab.simulation{ world = world, record = false }
        for _ = 1, 100 do
          sim:step(30)
          collectgarbage()
          sim:reset()
        end
        collectgarbage("generational")
    )");
    CHECK(lua.integer("sim.ticks") == 0);
}
