// The userdata every binding makes (scripting/src/lua_util.h): protected metatables, a __gc
// that destroys its object once, whatever it is called with, so no script reaches freed memory,
// and one handle per object (push_canonical) that never outlives it in the handles' table.
#include <catch2/catch.hpp>

#include <string>

#include "gaitlab/error.h"
#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::test::lua_dir;
using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;

namespace {

// one object of every gaitlab type a script can hold, in the global table `objects`
const char* kObjects = R"(
    objects = {}
    objects.robot = gaitlab.robot.chain{ modules = 3 }
    objects.group = objects.robot:group("pitch")
    objects.controller = gaitlab.controllers.sine{}
    objects.group:drive(objects.controller)
    objects.world = gaitlab.world()
    objects.world:add(objects.robot)
    objects.simulation = gaitlab.simulation{ world = objects.world, record = false }
    objects.class = gaitlab.controller{ name = "c", step = function() end }
    objects.actuation = objects.robot:actuation()
    objects.sensor = objects.robot:sensor{ kind = "joint", joint = 1 }
    objects.module = gaitlab.modules.y1
    objects.live = objects.simulation:live{ series = { "robot.com.x" } }
)";

}  // namespace

TEST_CASE("gaitlab's metatables are protected: getmetatable gives the type name", "[lua_util]") {
    LuaFixture lua;
    lua.run(kObjects);
    lua.run(R"(
        for name, obj in pairs(objects) do
          local mt = getmetatable(obj)
          assert(type(mt) == "string" and mt:find("^gaitlab%."), name)
          assert(not pcall(setmetatable, obj, {}), name)
        end
    )");
    CHECK(lua.string("getmetatable(objects.simulation)") == "gaitlab.Simulation");
    CHECK_THAT(lua.error_of("getmetatable(objects.robot).__gc(42)"),
               Catch::Contains("attempt to call a nil value (field '__gc')"));
}

TEST_CASE("__gc called by hand, with anything, never crashes and never runs twice", "[lua_util]") {
    LuaFixture lua;
    lua.run(kObjects);
    // through the debug library, which sees the real metatables: wrong arguments are ignored
    lua.run(R"(
        for name, obj in pairs(objects) do
          local gc = debug.getmetatable(obj).__gc
          gc(42)
          gc(nil)
          gc("robot")
          gc({})
          gc(io.stdout)
          for other, o in pairs(objects) do
            if other ~= name then gc(o) end  -- an object of another type: not this type's
          end
          assert(debug.getmetatable(obj) ~= nil, name .. " destroyed by a foreign __gc")
        end
    )");
    CHECK(lua.integer("#objects.robot:joints()") == 3);
    lua.run("objects.simulation:run(0.05)");
    // the right object: destroyed once, then unusable with an error instead of freed memory
    lua.run(R"(
        for name, obj in pairs(objects) do
          local gc = debug.getmetatable(obj).__gc
          gc(obj)
          gc(obj)
          assert(debug.getmetatable(obj) == nil, name)
        end
    )");
    CHECK_THAT(lua.error_of("objects.robot:joints()"),
               Catch::Contains("attempt to index a userdata value"));
    CHECK_THAT(lua.error_of("gaitlab.simulation{ world = objects.world }"),
               Catch::Contains("gaitlab.World expected, got userdata"));
    lua.run("collectgarbage() collectgarbage()");
}

TEST_CASE("a controller class collected while its instances run stays usable", "[lua_util]") {
    LuaFixture lua;
    lua.run(R"(
        local C = gaitlab.controller{ name = "c", values = { "t" },
          step = function(self, dt) self.t[1] = self.t[1] + dt end }
        robot = gaitlab.robot.chain{ modules = 2 }
        ctl = robot:group{ 1 }:drive(C())
        world = gaitlab.world()
        world:add(robot)
        sim = gaitlab.simulation{ world = world, record = false }
        debug.getmetatable(C).__gc(C)
        C = nil
        collectgarbage() collectgarbage()
        sim:run(0.3)
    )");
    CHECK(lua.number("ctl:values().t[1]") == Approx(0.3).margin(0.031));
}

TEST_CASE("bindings read argument tables raw: no script code runs inside a binding", "[lua_util]") {
    LuaFixture lua;
    lua.run(R"(
        calls = 0
        evil = { __index = function(t, k) calls = calls + 1 error("gotcha " .. k) end,
                 __newindex = function() calls = calls + 1 error("set") end,
                 __len = function() calls = calls + 1 error("len") end }
    )");
    CHECK(lua.error_of("gaitlab.robot.chain(setmetatable({}, evil))") ==
          "test:1: bad argument #1 to 'chain' (field 'modules': number of modules expected, got "
          "nil)");
    CHECK_THAT(lua.error_of("gaitlab.controller(setmetatable({ name = 'x' }, evil))"),
               Catch::Contains("field 'step': function expected, got nil"));
    lua.run("C = gaitlab.controller{ name = 'x', step = print, values = setmetatable({}, evil) }");
    // a controller that gives its own self a hostile metatable only breaks itself
    lua.run(R"(
        C = gaitlab.controller{ name = "y", values = { "t" }, params = { a = { 1, min = 0, max = 2 } },
          step = function(self) setmetatable(self, evil) self.t[1] = 1 end }
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group{ 1 }:drive(C{})
        sim = gaitlab.simulation{ world = world, record = false }
        sim:run(0.2)
        ctl.a = 1.5
        sim:run(0.2)
    )");
    CHECK(lua.number("ctl:values().t[1]") == 1);
    CHECK(lua.integer("calls") == 0);
}

TEST_CASE("strings keep their zero bytes, paths with one are refused", "[lua_util]") {
    LuaFixture lua;
    // a field keeps all of its string: "pitch-pitch\0x" is not "pitch-pitch"
    CHECK_THAT(lua.error_of("gaitlab.robot.chain{ modules = 2, connection = 'pitch-pitch\\0x' }"),
               Catch::Contains("unknown connection type"));
    CHECK_THAT(lua.error_of("gaitlab.controllers.sine{ ['amplitude\\0x'] = 3 }"),
               Catch::Contains("unknown key 'amplitude"));
    // the system would stop at the zero and open another file than the one checked
    CHECK(lua.error_of("gaitlab.robot.load('robot.xml\\0/../../x')") ==
          "test:1: a path cannot contain a zero byte (got 'robot.xml\\x00...')");
    CHECK_THAT(lua.error_of("gaitlab.controller.write_template('sine', 'a\\0b.lua')"),
               Catch::Contains("a path cannot contain a zero byte"));
    // a message quoting such a string shows all of it, the zero as \x00, and goes on after it
    CHECK_THAT(lua.error_of("gaitlab.robot.chain{ modules = 2, connection = 'pitch-pitch\\0x' }"),
               Catch::Contains("unknown connection type 'pitch-pitch\\x00x' (expected"));
    // names are looked up with all of their bytes: 'y1\0' is no module type, 's\0' no sensor
    CHECK_THAT(lua.error_of("gaitlab.robot.chain{ modules = 2, module = 'y1\\0' }"),
               Catch::Contains("unknown module type 'y1\\x00'"));
    lua.run(
        "nul_robot = gaitlab.robot.chain{ modules = 2 }; nul_robot:sensor{ kind = 'imu', "
        "module = 1, name = 's' }");
    CHECK_THAT(lua.error_of("nul_robot:sensor('s\\0')"), Catch::Contains("no sensor 's\\x00'"));
    CHECK_THAT(lua.error_of("nul_robot:sensor{ kind = 'imu\\0', module = 1 }"),
               Catch::Contains("unknown sensor kind 'imu\\x00'"));
    CHECK_THAT(lua.error_of("gaitlab.actuation{ groups = { { joints = 'pitch\\0', controller = "
                            "{ builtin = 'sine' } } } }"),
               Catch::Contains("'pitch\\x00'"));
    // a run folder with a zero byte would be another folder
    CHECK_THAT(lua.error_of("local w = gaitlab.world(); w:add(gaitlab.robot.chain{ modules = 2 })"
                            "; gaitlab.simulation{ world = w, record = { dir = 'run\\0x' } }"),
               Catch::Contains("the run folder 'run\\x00x' cannot contain a zero byte"));
}

namespace {

// err(f, ...): the message f(...) fails with, without a place when f is a C function, or "no
// error: " and what it returned (so a check on code that does not fail fails, and goes on)
const char* kErr = R"(
    function err(f, ...)
      local r = table.pack(pcall(f, ...))
      if r[1] then return "no error: " .. tostring(r[2]) .. ", " .. tostring(r[3]) end
      return tostring(r[2])
    end
)";

// a 3-module "snake" driven by a sine, with an imu, recorded for 0.1 s to DIR/run (opened as
// `run`) with a live buffer `live`
void record_snake(LuaFixture& lua, const TempDir& tmp) {
    lua.run(kErr);
    lua.run("DIR = '" + tmp.str() + "'");
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30 })
        sensor = robot:sensor{ kind = "imu", module = 1 }
        sim = gaitlab.simulation{ world = world, record = DIR .. "/run" }
        live = sim:live{ series = { "snake.com.x" } }
        sim:run(0.1)
        sim:record(false)
        run = assert(gaitlab.data.open(DIR .. "/run"))
    )");
}

}  // namespace

TEST_CASE("a zero byte: an actuation's parameter is its whole name", "[lua_util]") {
    LuaFixture lua;
    lua.run(kErr);
    // 'amplitude\0junk' is not amplitude (it was read up to the zero and set amplitude to 12)
    lua.run(
        "act = gaitlab.actuation{ groups = { { joints = 'pitch', controller = { builtin = 'sine', "
        "params = { ['amplitude\\0junk'] = 12 } } } } }");
    CHECK_THAT(lua.string("err(function() gaitlab.robot.chain{ modules = 3 }:actuate(act) end)"),
               Catch::Contains("controller 'sine' has no parameter 'amplitude\\x00junk'"));
}

TEST_CASE("a zero byte: a series name with one matches nothing", "[lua_util]") {
    TempDir tmp("lua_util_zero_series");
    LuaFixture lua;
    record_snake(lua, tmp);
    const std::string junk = "'snake.com.x\\x00junk'";
    CHECK_THAT(lua.string("err(function() run:get('snake.com.x\\0junk') end)"),
               Catch::Contains(junk));
    CHECK_THAT(lua.string("err(function() run:select('snake.com.x\\0junk') end)"),
               Catch::Contains(junk));
    CHECK_THAT(lua.string("err(function() run:select{ 'snake.com.x\\0junk' } end)"),
               Catch::Contains(junk));
    CHECK_THAT(lua.string("err(function() run:export{ series = 'snake.com.x\\0junk', file = DIR .. "
                          "'/x.csv' } end)"),
               Catch::Contains(junk));
    CHECK_THAT(lua.string("err(function() run:plot{ series = 'snake.com.x\\0junk', output = DIR .. "
                          "'/p.png' } end)"),
               Catch::Contains(junk));
    CHECK_THAT(lua.string("err(function() sim:live{ series = { 'snake.com.x\\0junk' } } end)"),
               Catch::Contains(junk));
    // a recording's series, and the simulation's own fields and methods
    CHECK_THAT(lua.string("err(gaitlab.simulation, { world = world, record = { dir = DIR .. "
                          "'/z', series = { 'snake.com.x\\0junk' } } })"),
               Catch::Contains("no series matches 'snake.com.x\\x00junk'"));
    CHECK(lua.boolean("sim['run\\0x'] == nil and sim['time\\0x'] == nil"));
}

TEST_CASE("a zero byte: a path with one is refused", "[lua_util]") {
    TempDir tmp("lua_util_zero_paths");
    LuaFixture lua;
    // the system would take the file named by the part before the zero (Lua's own require
    // hands its searchers that part, as it always has: require is Lua's, not gaitlab's)
    lua.run(kErr);
    lua.run("DIR = '" + tmp.str() + "'");
    lua.run(R"(
        local f = assert(io.open(DIR .. "/mod.lua", "w"))
        f:write("RAN = true return 'mod'")
        f:close()
        f = assert(io.open(DIR .. "/p.xml", "w"))
        f:write("RAN = true")
        f:close()
        package.path = DIR .. "/?.lua"
    )");
    CHECK(lua.string("err(gaitlab.world.load, DIR .. '/mod.lua\\0x')") ==
          "a path cannot contain a zero byte (got '" + tmp.file("mod.lua") + "\\x00...')");
    CHECK_THAT(lua.string("err(gaitlab.world.load, DIR .. '/p.xml\\0x')"),
               Catch::Contains("a path cannot contain a zero byte"));
    CHECK_THAT(lua.string("err(package.searchers[2], 'mod\\0evil')"),
               Catch::Contains("a path cannot contain a zero byte"));
    CHECK_THAT(lua.string("err(gaitlab.data.open, DIR .. '\\0')"),
               Catch::Contains("a path cannot contain a zero byte"));
    CHECK(lua.boolean("RAN == nil"));
    // with its name whole, the module is there
    CHECK(lua.string("(require('mod'))") == "mod");
    CHECK(lua.error_of("gaitlab.world.load(DIR .. '/p.xml\\0x')") ==
          "test:1: a path cannot contain a zero byte (got '" + tmp.file("p.xml") + "\\x00...')");
}

TEST_CASE("a zero byte: a handle's key with one finds nothing", "[lua_util]") {
    TempDir tmp("lua_util_zero_keys");
    LuaFixture lua;
    record_snake(lua, tmp);
    // 'name\0x' is no field, 'group\0x' no method
    lua.run("C = gaitlab.controller{ name = 'c', step = function() end }");
    for (const char* e : {"robot['name\\0x']", "robot['group\\0x']", "robot['chain\\0x']",
                          "C['name\\0x']", "gaitlab.modules.y1['name\\0x']", "run['dir\\0x']",
                          "run['select\\0x']", "live['series\\0x']", "live['get\\0x']"}) {
        INFO(e);
        CHECK(lua.boolean(std::string(e) + " == nil"));
    }
    CHECK_THAT(lua.string("err(function(k) return ctl[k] end, 'set\\0x')"),
               Catch::Contains("has no parameter or method 'set\\x00x'"));
    CHECK_THAT(lua.string("err(function(k) return sensor[k] end, 'read\\0x')"),
               Catch::Contains("has no field or method 'read\\x00x'"));
    CHECK_THAT(lua.string("err(function(k) return ctl[k] end, 'amplitude\\0x')"),
               Catch::Contains("has no parameter or method 'amplitude\\x00x'"));
    CHECK(lua.number("ctl.amplitude") == 30);
    CHECK(lua.string("robot.name") == "snake");
}

TEST_CASE("a zero byte: a Lua error's message keeps what follows it", "[lua_util]") {
    LuaFixture lua;
    lua.run(R"(
        Failing = gaitlab.controller{ name = "failing",
          step = function(self) error("step failed\0 at joint 3") end }
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group("pitch"):drive(Failing())
        sim = gaitlab.simulation{ world = world, record = false }
    )");
    CHECK(lua.error_of("sim:run(0.1)") == "test:3: step failed\\x00 at joint 3");
    CHECK(lua.string("ctl.error") == "test:3: step failed\\x00 at joint 3");
    // what `gaitlab run` prints of an error no one catches
    CHECK(lua.error_of("error('uncaught\\0 and after')") == "test:1: uncaught\\x00 and after");
    CHECK(
        lua.error_of("error(setmetatable({}, { __tostring = function() return 'obj\\0x' end }))") ==
        "test:1: obj\\x00x");
}

TEST_CASE("an integer field takes a number with an integer value, never a numeric string",
          "[lua_util]") {
    LuaFixture lua;
    lua.run("w = gaitlab.world(); r = gaitlab.robot.chain{ name = 'r', modules = 3 }; w:add(r)");
    const auto bad = [](const std::string& fn) {
        return "test:1: bad argument #1 to '" + fn + "' (";
    };
    // Lua's own conversion would read each as the number it spells
    CHECK(lua.error_of("gaitlab.robot.chain{ modules = '8' }") ==
          bad("chain") + "field 'modules': integer expected, got string)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, control_every = '30' }") ==
          bad("simulation") + "field 'control_every': integer expected, got string)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, solver_iterations = ' 20 ' }") ==
          bad("simulation") + "field 'solver_iterations': integer expected, got string)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, seed = '0x10' }") ==
          bad("simulation") + "field 'seed': integer expected, got string)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, record = { record_every = '2' } }") ==
          bad("simulation") +
              "field 'record': field 'record_every': integer expected, got string)");
    CHECK(lua.error_of("w:stairs{ steps = '4' }") ==
          bad("stairs") + "field 'steps': integer expected, got string)");
    CHECK(lua.error_of("w:rubble{ count = '5' }") ==
          bad("rubble") + "field 'count': integer expected, got string)");
    CHECK(lua.error_of("r:sensor{ kind = 'imu', module = '3' }") ==
          bad("sensor") + "field 'module': module number expected, got string)");
    CHECK(lua.error_of("r:sensor{ kind = 'joint', joint = '2' }") ==
          bad("sensor") + "field 'joint': joint number expected, got string)");
    // entries of lists
    CHECK(lua.error_of("r:group{ 1, '3' }") == bad("group") + "entry 2 is not a joint number)");
    CHECK(lua.error_of("gaitlab.actuation{ groups = { { joints = { '1' }, controller = { "
                       "builtin = 'sine' } } } }") ==
          bad("actuation") + "groups[1]: field 'joints': entry 1 is not a joint number)");
    CHECK(lua.error_of("w:heightfield{ samples = { '3', 2 }, heights = function() return 0 end "
                       "}") ==
          bad("heightfield") +
              "field 'samples': {nx, ny} with two integers in [2, 4096] expected)");
    // numbers are taken, a float with an integer value and a converted string too
    CHECK(lua.integer("#gaitlab.robot.chain{ modules = 8.0 }:joints()") == 8);
    CHECK(lua.integer("gaitlab.simulation{ world = w, control_every = 30.0, seed = "
                      "tonumber('7'), record = false }.control_every") == 30);
    CHECK(lua.integer("#r:group{ 1, 3.0 }:joints()") == 2);
}

TEST_CASE("an error message keeps what follows a zero byte", "[lua_util]") {
    const std::string with_zero("a\0b", 3);
    CHECK(std::string(gaitlab::Error("name '" + with_zero + "' unknown").what()) ==
          "name 'a\\x00b' unknown");
    CHECK(std::string(gaitlab::FormatError("got '" + with_zero + "'", "f.xml", 3).what()) ==
          "got 'a\\x00b'");
    CHECK(std::string(gaitlab::Error("plain").what()) == "plain");
}

TEST_CASE("a simulation whose handle is destroyed while it steps finishes its tick", "[lua_util]") {
    LuaFixture lua;
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 3 }
        local C = gaitlab.controller{ name = "gc", step = function(self)
          local mt = debug.getmetatable(SIM)
          if mt then mt.__gc(SIM) end
        end }
        robot:group{ 1 }:drive(C{})
        world = gaitlab.world()
        world:add(robot)
        SIM = gaitlab.simulation{ world = world, record = false }
    )");
    lua.run("SIM:run(0.5)");
    CHECK_THAT(lua.error_of("SIM:run(0.5)"), Catch::Contains("attempt to index a userdata value"));
    lua.run("collectgarbage() collectgarbage()");
}

TEST_CASE("a handle stands for its object only while it lives", "[lua_util][handles]") {
    LuaFixture lua;
    lua.run(kObjects);
    // the table that finds an object's handle again does not keep the handle alive
    lua.run(R"(
        gone = setmetatable({}, { __mode = "v" })
        gone.sensor = objects.robot:sensor{ kind = "imu", module = 2 }
        gone.group = objects.robot:group{ 2, 3 }
        gone.robot = objects.simulation:robot("robot")
        objects.robot = nil
        collectgarbage() collectgarbage()
    )");
    CHECK(lua.boolean("next(gone) == nil"));
    // a handle made again after that is a handle of the same robot, sensor and group
    CHECK(lua.integer("#objects.simulation:robot('robot'):joints()") == 3);
    CHECK(lua.string("objects.simulation:robot('robot'):sensor('imu2').name") == "imu2");
    CHECK(lua.integer("#objects.simulation:robot('robot'):group{ 2, 3 }") == 2);

    // a handle destroyed by hand (its __gc through the debug library) is never handed out
    // again: the object gets a new handle, and the destroyed one equals nothing
    lua.run(R"(
        robot = objects.simulation:robot("robot")
        sensor = robot:sensor("imu2")
        for _, h in ipairs({ robot, sensor, objects.controller, objects.group }) do
          debug.getmetatable(h).__gc(h)
        end
        again = objects.simulation:robot("robot")
    )");
    CHECK(lua.boolean("again ~= robot and robot ~= again"));
    CHECK(lua.integer("#again:joints()") == 3);
    CHECK(lua.string("again:sensor('imu2').name") == "imu2");
    CHECK(lua.boolean("again:sensor('imu2') ~= sensor"));
    CHECK(lua.number("again:controllers()[1].amplitude") > 0);
    CHECK(lua.boolean("again:controllers()[1] ~= objects.controller"));
    CHECK(lua.integer("#again:group('pitch')") == 3);

    // nor is one whose object was freed and whose address a new object took: each new robot
    // gets a handle of its own, never the destroyed one of the robot before it
    lua.run(R"(
        for i = 1, 50 do
          local old = gaitlab.robot.chain{ name = "old" .. i, modules = 1 }
          debug.getmetatable(old).__gc(old)
          local new = gaitlab.robot.chain{ name = "new" .. i, modules = 1 }
          assert(new.name == "new" .. i and new ~= old, i)
          keep = { old, new }
        end
    )");
}
