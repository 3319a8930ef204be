// Hot reload of controller files (scripting/src/hot_reload.cpp): real files in a temporary
// folder rewritten while a simulation runs; parameters and values carried over by name; broken
// or deleted versions keep the last good one running and are reported with file and line.
// Also the sandbox controller files run in.
#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;
namespace fs = std::filesystem;

namespace {

// sets every joint to gain degrees and counts its steps
const char* kProbeV1 = R"(return gaitlab.controller{
  name = "probe",
  params = { gain = { 10, min = 0, max = 50 }, old = { 1, min = 0, max = 2 } },
  values = { "count", "gone" },
  step = function(self, dt)
    for m = 1, self.joints do
      self.count[m] = self.count[m] + 1
      self:set_angle(m, self.gain)
    end
  end,
}
)";

// a different output, a new parameter (default 5) and a new value; 'old' and 'gone' are dropped
const char* kProbeV2 = R"(return gaitlab.controller{
  name = "probe",
  params = { gain = { 10, min = 0, max = 50 }, bias = { 5, min = 0, max = 10 } },
  values = { "count", "extra" },
  step = function(self, dt)
    for m = 1, self.joints do
      self.count[m] = self.count[m] + 1
      self.extra[m] = 7
      self:set_angle(m, -(self.gain + self.bias))
    end
  end,
}
)";

const char* kProbeSyntaxError = R"(return gaitlab.controller{
  name = "probe",
  step = function(self, dt)
    self:set_angle(1, 3 +)
  end,
}
)";

const char* kProbeLoadError = R"(local x = nil
local y = x.field
return gaitlab.controller{ name = "probe", step = function() end }
)";

}  // namespace

TEST_CASE("a changed controller file replaces the running version at the next control tick",
          "[hot_reload]") {
    TempDir dir("reload");
    const std::string file = dir.file("probe.lua");
    write_text(file, kProbeV1);
    LuaFixture lua;
    std::vector<std::string> reports;
    lua.host.set_reporter([&](const std::string& m) { reports.push_back(m); });
    lua.run("FILE = '" + file + "'");
    lua.run(R"(
        Probe = gaitlab.controller.load(FILE)
        robot = gaitlab.robot.chain{ modules = 3 }
        world = gaitlab.world()
        world:add(robot)
        a = robot:group{ 1 }:drive(Probe{ gain = 20 })
        b = robot:group{ 2 }:drive(Probe{ gain = 30, old = 2 })
        sim = gaitlab.simulation{ world = world }
        sim:run(0.3)
    )");
    CHECK(lua.number("robot:joints()[1].target") == Approx(20));
    CHECK(lua.number("robot:joints()[2].target") == Approx(30));
    CHECK(lua.integer("Probe.version") == 0);
    const double count = lua.number("a:values().count[1]");
    CHECK(count == 10);

    // v2 while the simulation exists; the first control tick after the check interval (0.2 s
    // of wall time) runs it, in both groups
    write_text(file, kProbeV2);
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    lua.run("sim:step(1)");
    CHECK(lua.integer("Probe.version") == 1);
    CHECK(lua.number("robot:joints()[1].target") == Approx(-25));
    CHECK(lua.number("robot:joints()[2].target") == Approx(-35));
    CHECK(lua.number("a:values().count[1]") == count + 1);  // values kept by name
    CHECK(lua.number("a:values().extra[1]") == 7);
    CHECK(lua.boolean("a:values().gone == nil"));
    CHECK(lua.number("a.gain") == 20);  // parameters kept by name
    CHECK(lua.number("b.gain") == 30);
    CHECK(lua.number("a.bias") == 5);  // new ones take their default
    CHECK(lua.boolean("a:params().old == nil"));
    CHECK(reports.empty());
    lua.run("a.bias = 10  sim:run(0.1)");
    CHECK(lua.number("robot:joints()[1].target") == Approx(-30));

    // a syntax error keeps v2 running and names the file and line
    write_text(file, kProbeSyntaxError);
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    lua.run("sim:run(0.1)");
    const std::string syntax = file + ":4: unexpected symbol near ')'";
    REQUIRE(reports.size() == 1);
    CHECK(reports[0] == "reload failed: " + syntax);
    CHECK(lua.string("Probe.reload_error") == syntax);
    CHECK(lua.integer("Probe.version") == 1);
    CHECK(lua.number("robot:joints()[1].target") == Approx(-30));
    CHECK(lua.boolean("a.failed") == false);
    // reload() forces a new attempt and says why it failed
    lua.run("ok, err = gaitlab.controller.reload()");
    CHECK(lua.boolean("ok") == false);
    CHECK(lua.string("err") == syntax);
    CHECK(reports.size() == 2);

    // so does an error while the file runs
    write_text(file, kProbeLoadError);
    lua.run("ok, err = gaitlab.controller.reload()");
    CHECK(lua.string("err") == file + ":2: attempt to index a nil value (local 'x')");
    lua.run("sim:run(0.1)");
    CHECK(lua.number("robot:joints()[1].target") == Approx(-30));

    // a deleted file keeps the last good version, reported once
    fs::remove(file);
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    reports.clear();
    lua.run("sim:run(0.5)");
    REQUIRE(reports.size() == 1);
    CHECK(reports[0] ==
          "reload failed: " + file +
              ": cannot read the file (No such file or directory); 'probe' keeps its last good "
              "version");
    CHECK(lua.number("robot:joints()[2].target") == Approx(-35));

    // back again: v1 runs, parameters still carried over
    write_text(file, kProbeV1);
    lua.run("ok, err = gaitlab.controller.reload()");
    CHECK(lua.boolean("ok"));
    CHECK(lua.boolean("err == nil"));
    CHECK(lua.boolean("Probe.reload_error == nil"));
    lua.run("sim:step(30)");
    CHECK(lua.number("robot:joints()[1].target") == Approx(20));
    CHECK(lua.number("a.old") == 1);
}

// Lua that defines write_level(level), a controller file at FILE holding joint 1 at `level`
// degrees, writes it at 10 and drives a 2-module robot's first joint with it in `sim`
const char* const kLevelSim = R"(
    function write_level(level)
        local f = assert(io.open(FILE, "w"))
        f:write(string.format([[return gaitlab.controller{ name = "level",
          step = function(self) self:set_angle(1, %d) end }
        ]], level))
        f:close()
    end
    write_level(10)
    local Level = gaitlab.controller.load(FILE)
    robot = gaitlab.robot.chain{ modules = 2 }
    world = gaitlab.world()
    world:add(robot)
    robot:group{ 1 }:drive(Level())
    sim = gaitlab.simulation{ world = world }
)";

TEST_CASE("a script can rewrite its controller while sim:run runs it", "[hot_reload]") {
    TempDir dir("script");
    LuaFixture lua;
    lua.host.set_reload_interval(0);
    lua.run("FILE = '" + dir.file("level.lua") + "'");
    lua.run(kLevelSim);
    lua.run(R"(
        targets = {}
        sim:run(0.1)
        targets[1] = robot:joints()[1].target
        write_level(25)
        sim:run(0.1)
        targets[2] = robot:joints()[1].target
    )");
    CHECK(lua.number("targets[1]") == Approx(10));
    CHECK(lua.number("targets[2]") == Approx(25));
}

TEST_CASE("a shorter reload interval takes effect at once, not after the longer one begun",
          "[hot_reload]") {
    TempDir dir("interval");
    LuaFixture lua;
    lua.host.set_reload_interval(3600);  // the next check an hour away
    lua.run("FILE = '" + dir.file("level.lua") + "'");
    lua.run(kLevelSim);
    lua.run("sim:run(0.1) write_level(25) sim:run(0.1) before = robot:joints()[1].target");
    CHECK(lua.number("before") == Approx(10));  // within the hour: not checked
    lua.host.set_reload_interval(0);
    lua.run("sim:run(0.1) after = robot:joints()[1].target");
    CHECK(lua.number("after") == Approx(25));
}

TEST_CASE("snapshot and on_reload carry state the names do not", "[hot_reload]") {
    TempDir dir("hooks");
    const std::string file = dir.file("hooks.lua");
    write_text(file, R"(return gaitlab.controller{
  name = "hooks",
  snapshot = function(self) return { steps = self.steps } end,
  step = function(self, dt)
    self.steps = (self.steps or 0) + 1
    self:set_angle(1, 0)
  end,
}
)");
    LuaFixture lua;
    lua.run("FILE = '" + file + "'");
    lua.run(R"(
        Hooks = gaitlab.controller.load(FILE)
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        robot:group{ 1 }:drive(Hooks())
        sim = gaitlab.simulation{ world = world }
        sim:run(0.3)
    )");
    write_text(file, R"(return gaitlab.controller{
  name = "hooks",
  on_reload = function(self, snapshot) self.restored = snapshot.steps end,
  step = function(self, dt) self:set_angle(1, self.restored) end,
}
)");
    lua.run("ctl = robot:controllers()[1]  assert(gaitlab.controller.reload())  sim:step(1)");
    CHECK(lua.number("robot:joints()[1].target") == Approx(10));
    // the class and its instance are the ones they were: the same handles
    CHECK(lua.boolean("rawequal(robot:controllers()[1], ctl)"));
    CHECK(lua.boolean("rawequal(gaitlab.controller.load(FILE), Hooks)"));
    CHECK(lua.error_of("gaitlab.controller{ name = 'x', step = print, on_reload = 1 }") ==
          "test:1: bad argument #1 to 'controller' (field 'on_reload': function expected, got "
          "number)");
}

TEST_CASE("saving a fixed file revives a controller that failed", "[hot_reload]") {
    TempDir dir("revive");
    const std::string file = dir.file("buggy.lua");
    // fails from its 5th step on: a typo a student would make
    write_text(file, R"(return gaitlab.controller{
  name = "buggy",
  values = { "n" },
  step = function(self, dt)
    self.n[1] = self.n[1] + 1
    if self.n[1] >= 5 then self:set_angle(1, self.amplitde * 2) end
    self:set_angle(1, 10)
  end,
}
)");
    LuaFixture lua;
    std::vector<std::string> reports;
    lua.host.set_reporter([&](const std::string& m) { reports.push_back(m); });
    lua.run("FILE = '" + file + "'");
    lua.run(R"(
        Buggy = gaitlab.controller.load(FILE)
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group{ 1 }:drive(Buggy())
        sim = gaitlab.simulation{ world = world, on_controller_error = "pause" }
        sim:run(10)
    )");
    CHECK(lua.boolean("sim.paused"));
    CHECK(lua.boolean("ctl.failed"));
    REQUIRE(reports.size() == 1);
    CAPTURE(reports[0]);
    CHECK(reports[0].rfind("controller 'buggy' failed: " + file +
                               ":6: attempt to perform arithmetic on a nil value (field "
                               "'amplitde')",
                           0) == 0);
    write_text(file, R"(return gaitlab.controller{
  name = "buggy",
  values = { "n" },
  step = function(self, dt)
    self.n[1] = self.n[1] + 1
    self:set_angle(1, 25)
  end,
}
)");
    lua.run("assert(gaitlab.controller.reload())");
    CHECK(lua.boolean("ctl.failed") == false);
    lua.run("sim:run(0.1)");
    CHECK(lua.boolean("sim.paused") == false);
    CHECK(lua.number("robot:joints()[1].target") == Approx(25));
    CHECK(lua.number("ctl:values().n[1]") > 5);  // it goes on from the state it had
    CHECK(reports.size() == 1);
}

TEST_CASE("controller files run in a sandbox unless the script opts out", "[hot_reload]") {
    TempDir dir("sandbox");
    const std::string body = R"(
  return gaitlab.controller{ name = "s", step = function(self) self:set_angle(1, 0) end }
)";
    write_text(dir.file("closed.lua"), R"(
  assert(os == nil and io == nil and require == nil and debug == nil, "not sandboxed")
  assert(load == nil and loadfile == nil and dofile == nil and package == nil)
  assert(math.sin and string.format and table.concat and utf8.char and pairs and print)
  assert(gaitlab.robot == nil and _G.gaitlab.controller)
  math.sin = nil  -- a copy: the script's math keeps its sin
)" + std::string(body));
    write_text(dir.file("open.lua"), "assert(os.time and io.open, 'not open')" + std::string(body));
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run("gaitlab.controller.load(DIR .. '/closed.lua')");
    CHECK(lua.boolean("math.sin ~= nil"));
    CHECK(lua.error_of("gaitlab.controller.load(DIR .. '/open.lua')") ==
          dir.file("open.lua") + ":1: attempt to index a nil value (global 'os')");
    lua.run("gaitlab.controller.load(DIR .. '/open.lua', { sandbox = false })");
    CHECK(lua.error_of("gaitlab.controller.load(DIR .. '/open.lua', { sandbx = false })") ==
          "test:1: bad argument #2 to 'load' (unknown key 'sandbx'; did you mean 'sandbox'?)");
}

TEST_CASE("a snapshot that makes or drops instances of its own class is safe", "[hot_reload]") {
    TempDir tmp("reload_instances");
    LuaFixture lua;
    const std::string file = tmp / "c.lua";
    const char* kBreeder = R"(return gaitlab.controller{ name = "c",
  step = function(self, dt) end,
  snapshot = function(self)
    -- new instances of this very class, and garbage for the collector, while the reload
    -- walks the class's instances
    for i = 1, 50 do MADE[#MADE + 1] = CLASS{} end
    for i = 1, 50 do CLASS{} end
    collectgarbage()
    return {}
  end })";
    write_text(file, kBreeder);
    lua.run("MADE = {} CLASS = gaitlab.controller.load('" + file + "', { sandbox = false })");
    lua.run(R"(
        for i = 1, 20 do CLASS{} end
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group{ 1 }:drive(CLASS{})
        sim = gaitlab.simulation{ world = world, record = false }
        sim:run(0.1)
    )");
    write_text(file, std::string(kBreeder) + "\n");
    lua.run("assert(gaitlab.controller.reload())");
    lua.run("sim:run(0.1)");
    CHECK(lua.integer("CLASS.version") == 1);
    CHECK(lua.integer("#MADE") >= 50);
}
