// Lua ⇄ XML: whatever a robot, environment, simulation or actuation file can say, a script can
// say with the same name and meaning. Every attribute of gaitlab::xml_schema() (the allow-lists
// the XML readers use) has its Lua key here, which a bad value must reach; and each file kind is
// built once from XML and once from Lua, and both are written with the engine's XML writer.
#include <catch2/catch.hpp>

#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "gaitlab/xml.h"
#include "gaitlab/xml_schema.h"
#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;

namespace {

// defined before each probe
const char* kSetup = R"(
r = gaitlab.robot.chain{ name = 'probe', modules = 2 }
w = gaitlab.world{}
two = { { name = 'a', size = {0.1, 0.1, 0.1}, mass = 1 },
        { name = 'b', size = {0.1, 0.1, 0.1}, mass = 1, position = {0.1, 0, 0} } }
)";

// How a script says one attribute: a chunk in which BAD stands for the attribute's value, and
// what the message of a wrong value must contain (the Lua key that took it).
struct Probe {
    std::string code;
    std::string names;
};

using Key = std::tuple<std::string, std::string, std::string>;  // file, element, attribute

std::map<Key, Probe> probes() {
    std::map<Key, Probe> p;
    auto add = [&](const std::string& file, const std::string& element,
                   const std::vector<std::string>& attrs, const std::string& code,
                   const std::string& names = "field '$'") {
        for (const std::string& a : attrs) {
            std::string c = code, n = names;
            for (std::string* s : {&c, &n}) {
                for (size_t at; (at = s->find('$')) != std::string::npos;)
                    s->replace(at, 1, a);
            }
            p[{file, element, a}] = {c, n};
        }
    };
    add("robot", "robot", {"name", "self_collision"},
        "gaitlab.robot.chain{ modules = 2, $ = BAD }");
    add("robot", "chain", {"modules"}, "gaitlab.robot.chain{ $ = BAD }");
    add("robot", "chain", {"connection", "module"}, "gaitlab.robot.chain{ modules = 2, $ = BAD }");
    add("robot", "module",
        {"shape", "length", "width", "height", "radius", "mass", "axis", "min", "max", "friction",
         "kp", "max_speed", "max_torque"},
        "gaitlab.module{ name = 'probe_m', $ = BAD }");
    add("robot", "module", {"name"}, "gaitlab.module{ name = BAD }");
    add("robot", "body",
        {"name", "shape", "size", "mass", "position", "orientation", "friction", "inertia", "com"},
        "gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 1, 1}, mass = 1, $ = BAD } } }",
        "bodies[1]: field '$'");
    add("robot", "joint",
        {"name", "role", "parent", "child", "pivot", "axis", "min", "max", "kp", "max_speed",
         "max_torque"},
        "gaitlab.robot.new{ bodies = two, joints = { { name = 'j', parent = 'a', child = 'b', "
        "pivot = {0.05, 0, 0}, axis = {0, 1, 0}, $ = BAD } } }",
        "joints[1]: field '$'");
    add("robot", "sensor", {"name", "module", "half", "direction", "max_range", "enabled"},
        "r:sensor{ kind = 'range', module = 1, $ = BAD }");
    add("robot", "sensor", {"joint"}, "r:sensor{ kind = 'joint', joint = BAD }");
    add("robot", "sensor", {"kind"}, "r:sensor{ kind = BAD }", "kind");
    add("environment", "environment", {"gravity"}, "gaitlab.world{ $ = BAD }");
    add("environment", "floor", {"enabled", "friction", "rigid", "stiffness", "damping"},
        "gaitlab.world{ floor = { $ = BAD } }");
    for (const char* kind : {"box", "wall", "ramp", "stairs", "cylinder", "pipe", "rubble"}) {
        add("environment", kind,
            {"size",        "position",   "yaw",       "orientation", "mass",       "friction",
             "length",      "height",     "thickness", "slope",       "width",      "steps",
             "step_height", "step_depth", "landing",   "radius",      "lying",      "sides",
             "count",       "min_size",   "max_size",  "min_height",  "max_height", "seed"},
            std::string("w:") + kind + "{ $ = BAD }");
    }
    add("environment", "heightfield",
        {"length", "width", "max_height", "position", "yaw", "friction", "image", "samples"},
        "w:heightfield{ heights = { {0, 0}, {0, 0} }, $ = BAD }");
    add("environment", "place", {"position", "yaw", "orientation"},
        "w:place{ robot = 'probe', $ = BAD }");
    add("environment", "place", {"robot"}, "w:place{ robot = BAD }");
    add("simulation", "simulation",
        {"name", "duration", "dt", "control_every", "solver_iterations", "seed",
         "on_controller_error", "solver", "newton_steps"},
        "gaitlab.simulation{ world = w, $ = BAD }");
    // the files a simulation file names are the objects a script passes
    add("simulation", "environment", {"file"}, "gaitlab.simulation{ world = BAD }",
        "field 'world'");
    add("simulation", "robot", {"file"}, "w:add(BAD)", "gaitlab.Robot expected");
    add("simulation", "robot", {"actuation"}, "r:actuate(BAD)", "gaitlab.Actuation expected");
    add("simulation", "record", {"enabled", "dir", "every", "flush_seconds"},
        "gaitlab.simulation{ world = w, record = { $ = BAD } }", "field 'record': field '$'");
    add("actuation", "group", {"joints"},
        "gaitlab.actuation{ groups = { { joints = BAD, controller = { builtin = 'sine' } } } }",
        "groups[1]: field '$'");
    add("actuation", "controller", {"builtin", "file", "template"},
        "gaitlab.actuation{ groups = { { joints = 'all', controller = { $ = BAD } } } }",
        "groups[1]: field '$'");
    return p;
}

}  // namespace

TEST_CASE("every attribute of every XML file has its Lua key", "[xml_lua]") {
    const std::map<Key, Probe> all = probes();
    size_t checked = 0;
    for (const gaitlab::XmlElementSchema& e : gaitlab::xml_schema()) {
        for (const std::string& a : e.attributes) {
            INFO("<" << e.element << " " << a << "> of " << e.file << " files");
            const auto it = all.find({e.file, e.element, a});
            // a new attribute needs its Lua key, and a probe here that reaches it
            REQUIRE(it != all.end());
            LuaFixture lua;
            lua.run(kSetup);
            std::string code = it->second.code;
            code.replace(code.find("BAD"), 3, "print");  // a function: no key takes one
            INFO(code);
            const std::string message = lua.error_of(code);
            INFO(message);
            CHECK(message.find(it->second.names) != std::string::npos);
            CHECK(message.find("unknown key") == std::string::npos);
            ++checked;
        }
    }
    CHECK(checked > 100);
}

namespace {

// runs `lua_code` (which saves what it builds to OUT) and returns the file written
std::string saved_by(const std::string& lua_code, const TempDir& dir, const std::string& name) {
    LuaFixture lua;
    std::string code = lua_code;
    const std::string out = dir / name;
    for (size_t at; (at = code.find("OUT")) != std::string::npos;)
        code.replace(at, 3, "'" + out + "'");
    lua.run(code);
    return gaitlab::test::read_text(out);
}

}  // namespace

TEST_CASE("a chain robot with a custom module and sensors is the same from XML and Lua",
          "[xml_lua]") {
    const std::string xml = R"(<?xml version="1.0"?>
<gaitlab version="1">
  <robot name="snake" self_collision="true">
    <chain modules="3" connection="pitch-yaw">
      <module name="wide" shape="cylinder" length="0.06" width="0.05" height="0.04"
              radius="0.02" mass="0.08" axis="twist" min="-60" max="75" friction="0.7"
              kp="6" max_speed="3.5" max_torque="0.5"/>
    </chain>
    <sensor kind="joint" name="j2" joint="2" enabled="false"/>
    <sensor kind="imu" name="head" module="3" half="tail"/>
    <sensor kind="contact" name="touch" module="1"/>
    <sensor kind="range" name="eye" module="3" half="head" direction="0 1 0" max_range="0.8"/>
    <sensor kind="position" name="where"/>
  </robot>
</gaitlab>
)";
    const std::string from_xml = gaitlab::format_robot(gaitlab::parse_robot(xml, "snake.xml"));
    TempDir dir("xml_lua_chain");
    const std::string from_lua = saved_by(R"(
local wide = gaitlab.module{ name = 'wide', shape = 'cylinder', length = 0.06, width = 0.05,
    height = 0.04, radius = 0.02, mass = 0.08, axis = 'twist', min = -60, max = 75,
    friction = 0.7, kp = 6, max_speed = math.deg(3.5), max_torque = 0.5 }
local r = gaitlab.robot.chain{ name = 'snake', self_collision = true, modules = 3,
    connection = 'pitch-yaw', module = wide }
r:sensor{ kind = 'joint', name = 'j2', joint = 2, enabled = false }
r:sensor{ kind = 'imu', name = 'head', module = 3, half = 'tail' }
r:sensor{ kind = 'contact', name = 'touch', module = 1 }
r:sensor{ kind = 'range', name = 'eye', module = 3, half = 'head', direction = {0, 1, 0},
          max_range = 0.8 }
r:sensor{ kind = 'position', name = 'where' }
assert(r:save(OUT))
)",
                                          dir, "snake.robot.xml");
    CHECK(from_lua == from_xml);
    CHECK(from_xml.find("self_collision=\"true\"") != std::string::npos);
    CHECK(from_xml.find("name=\"wide\"") != std::string::npos);
}

TEST_CASE("a robot of bodies and joints is the same from XML and Lua", "[xml_lua]") {
    const std::string xml = R"(<?xml version="1.0"?>
<gaitlab version="1">
  <robot name="arm" self_collision="true">
    <body name="base" size="0.1 0.1 0.05" mass="0.5" position="0 0 0.025" friction="0.9"
          inertia="0.0004 0.0005 0.0008"/>
    <body name="link" shape="cylinder" size="0.12 0.03 0.03" mass="0.1" position="0.11 0 0.025"
          orientation="0.7071067811865476 0 0 0.7071067811865476" friction="0.4"
          inertia="1e-5 1e-4 1e-4" com="0.02 0 -0.005"/>
    <joint name="shoulder" role="yaw" parent="base" child="link" pivot="0.05 0 0.025"
           axis="0 0 1" min="-45" max="30" kp="5" max_speed="2" max_torque="0.3"/>
  </robot>
</gaitlab>
)";
    const std::string from_xml = gaitlab::format_robot(gaitlab::parse_robot(xml, "arm.xml"));
    TempDir dir("xml_lua_parts");
    const std::string from_lua = saved_by(R"(
local r = gaitlab.robot.new{ name = 'arm', self_collision = true,
  bodies = {
    { name = 'base', size = {0.1, 0.1, 0.05}, mass = 0.5, position = {0, 0, 0.025},
      friction = 0.9, inertia = {0.0004, 0.0005, 0.0008} },
    { name = 'link', shape = 'cylinder', size = {0.12, 0.03, 0.03}, mass = 0.1,
      position = {0.11, 0, 0.025}, orientation = {0.7071067811865476, 0, 0, 0.7071067811865476},
      friction = 0.4, inertia = {1e-5, 1e-4, 1e-4}, com = {0.02, 0, -0.005} } },
  joints = {
    { name = 'shoulder', role = 'yaw', parent = 'base', child = 'link', pivot = {0.05, 0, 0.025},
      axis = {0, 0, 1}, min = -45, max = 30, kp = 5, max_speed = math.deg(2), max_torque = 0.3 } } }
assert(#r == 1 and r.chain == nil)
local i = r:bodies()[2].inertia
assert(i.x == 1e-5 and i.y == 1e-4 and i.z == 1e-4)
local c, none = r:bodies()[2].com, r:bodies()[1].com
assert(c.x == 0.02 and c.y == 0 and c.z == -0.005)
assert(none.x == 0 and none.y == 0 and none.z == 0)
assert(r:save(OUT))
)",
                                          dir, "arm.robot.xml");
    CHECK(from_lua == from_xml);
    CHECK(from_xml.find("<joint name=\"shoulder\"") != std::string::npos);
    CHECK(from_xml.find("inertia=\"0.0004 0.0005 0.0008\"") != std::string::npos);
    // and back: the file loaded in Lua gives the same inertia
    LuaFixture lua;
    lua.run("r = assert(gaitlab.robot.load('" + (dir / "arm.robot.xml") + "'))");
    CHECK(lua.number("r:bodies()[1].inertia.y") == 0.0005);
    CHECK(lua.number("r:bodies()[2].inertia.x") == 1e-5);
    CHECK(lua.number("r:bodies()[2].com.z") == -0.005);
    CHECK(from_xml.find("com=\"0.02 0 -0.005\"") != std::string::npos);
    CHECK(from_xml.find("com=") == from_xml.rfind("com="));  // the base has none
}

TEST_CASE("an environment with every object kind is the same from XML and Lua", "[xml_lua]") {
    const std::string xml = R"(<?xml version="1.0"?>
<gaitlab version="1">
  <environment gravity="0 0 -3.7">
    <floor enabled="false" friction="0.6" stiffness="20000" damping="15.5"/>
    <box size="0.2 0.1 0.05" position="1 0 0.025" yaw="30" mass="0.2" friction="0.5"/>
    <box size="0.1 0.1 0.1" position="0 1 0.5"
         orientation="0.7071067811865476 0.7071067811865476 0 0"/>
    <wall length="2" height="0.3" thickness="0.05" position="0 -1 0" yaw="90" friction="0.8"/>
    <ramp slope="15" length="0.6" width="0.4" position="2 0 0" yaw="-10" friction="0.9"/>
    <stairs steps="4" step_height="0.02" step_depth="0.1" width="0.5" landing="0.3"
            position="3 0 0" yaw="180" friction="0.7"/>
    <cylinder radius="0.05" length="0.3" lying="true" position="0 2 0.05" yaw="45" mass="0.3"
              friction="0.6"/>
    <pipe radius="0.1" thickness="0.01" length="1" sides="8" position="-2 0 0.11" yaw="5"
          friction="0.4"/>
    <rubble length="1" width="0.8" count="20" min_size="0.01" max_size="0.03" min_height="0.005"
            max_height="0.02" seed="7" position="0 -3 0" yaw="12" friction="0.9"/>
    <heightfield length="1" width="0.5" position="4 0 0" yaw="20" friction="0.8" samples="3 2">
      <heights>0 0.01 0.02
               0.03 0.04 0.05</heights>
    </heightfield>
    <place robot="snake" position="0.5 0.5 0" yaw="90"/>
    <place robot="arm" position="0 0 0.1" orientation="0 0 0 1"/>
  </environment>
</gaitlab>
)";
    TempDir dir("xml_lua_env");
    const std::string out = dir / "world.environment.xml";
    const std::string from_xml =
        gaitlab::format_environment(gaitlab::parse_environment(xml, "world.xml"), out);
    const std::string from_lua = saved_by(R"(
local w = gaitlab.world{ gravity = {0, 0, -3.7},
                        floor = { enabled = false, friction = 0.6, stiffness = 2e4, damping = 15.5 } }
w:box{ size = {0.2, 0.1, 0.05}, position = {1, 0, 0.025}, yaw = 30, mass = 0.2, friction = 0.5 }
w:box{ size = {0.1, 0.1, 0.1}, position = {0, 1, 0.5},
       orientation = {0.7071067811865476, 0.7071067811865476, 0, 0} }
w:wall{ length = 2, height = 0.3, thickness = 0.05, position = {0, -1, 0}, yaw = 90,
        friction = 0.8 }
w:ramp{ slope = 15, length = 0.6, width = 0.4, position = {2, 0, 0}, yaw = -10, friction = 0.9 }
w:stairs{ steps = 4, step_height = 0.02, step_depth = 0.1, width = 0.5, landing = 0.3,
          position = {3, 0, 0}, yaw = 180, friction = 0.7 }
w:cylinder{ radius = 0.05, length = 0.3, lying = true, position = {0, 2, 0.05}, yaw = 45,
            mass = 0.3, friction = 0.6 }
w:pipe{ radius = 0.1, thickness = 0.01, length = 1, sides = 8, position = {-2, 0, 0.11},
        yaw = 5, friction = 0.4 }
w:rubble{ length = 1, width = 0.8, count = 20, min_size = 0.01, max_size = 0.03,
          min_height = 0.005, max_height = 0.02, seed = 7, position = {0, -3, 0}, yaw = 12,
          friction = 0.9 }
w:heightfield{ length = 1, width = 0.5, position = {4, 0, 0}, yaw = 20, friction = 0.8,
               heights = { {0, 0.01, 0.02}, {0.03, 0.04, 0.05} } }
w:place{ robot = 'snake', position = {0.5, 0.5, 0}, yaw = 90 }
w:place{ robot = 'arm', position = {0, 0, 0.1}, orientation = {0, 0, 0, 1} }
assert(w:save(OUT))
)",
                                          dir, "world.environment.xml");
    CHECK(from_lua == from_xml);
    CHECK(from_xml.find("enabled=\"false\"") != std::string::npos);
    CHECK(from_xml.find("stiffness=\"20000\" damping=\"15.5\"") != std::string::npos);
    CHECK(from_xml.find("<place robot=\"arm\"") != std::string::npos);
}

TEST_CASE("a world:place puts a robot added without a pose where a <place> would", "[xml_lua]") {
    LuaFixture lua;
    lua.run(R"(
w = gaitlab.world{}
w:place{ robot = 'snake', position = {1, 2, 0}, yaw = 90 }
s = gaitlab.robot.chain{ name = 'snake', modules = 2 }
w:add(s)
sim = gaitlab.simulation{ world = w }
p = s:position()
)");
    CHECK(lua.number("p.x") == Approx(1).margin(0.05));
    CHECK(lua.number("p.y") > 1.9);
    CHECK(lua.number("math.abs(s:heading() - 90)") < 1);
}

TEST_CASE("an actuation is the same from XML and Lua", "[xml_lua]") {
    const std::string xml = R"(<?xml version="1.0"?>
<gaitlab version="1">
  <actuation>
    <group joints="pitch">
      <controller builtin="sine" amplitude="30" frequency="2"/>
    </group>
    <group joints="1 4">
      <controller builtin="offset" angle="10"/>
    </group>
    <group joints="yaw">
      <controller template="cpg_chain"/>
    </group>
  </actuation>
</gaitlab>
)";
    const std::string from_xml =
        gaitlab::format_actuation(gaitlab::parse_actuation(xml, "act.xml"));
    TempDir dir("xml_lua_act");
    const std::string from_lua = saved_by(R"(
local a = gaitlab.actuation{ groups = {
  { joints = 'pitch', controller = { builtin = 'sine', params = { amplitude = 30, frequency = 2 } } },
  { joints = {1, 4}, controller = { builtin = 'offset', params = { angle = 10 } } },
  { joints = 'yaw', controller = { template = 'cpg_chain' } } } }
assert(#a == 3)
assert(a:save(OUT))
-- it drives a robot as the file's would
local r = gaitlab.robot.chain{ modules = 4, connection = 'pitch-yaw' }
assert(#r:actuate(a) == 3)
)",
                                          dir, "act.actuation.xml");
    CHECK(from_lua == from_xml);
}

TEST_CASE("a simulation's settings are the same from XML and Lua", "[xml_lua]") {
    TempDir dir("xml_lua_sim");
    gaitlab::test::write_text(dir / "env.xml", R"(<?xml version="1.0"?>
<gaitlab version="1"><environment gravity="0 0 -9.81">
  <place robot="snake" position="0 0 0"/></environment></gaitlab>
)");
    gaitlab::test::write_text(dir / "snake.xml", R"(<?xml version="1.0"?>
<gaitlab version="1"><robot name="snake"><chain modules="4"/></robot></gaitlab>
)");
    gaitlab::test::write_text(dir / "act.xml", R"(<?xml version="1.0"?>
<gaitlab version="1"><actuation><group joints="pitch">
  <controller builtin="sine" amplitude="20" frequency="0.5" phase="120" phase0="0" offset="0"/>
</group></actuation></gaitlab>
)");
    const std::string xml = R"(<?xml version="1.0"?>
<gaitlab version="1">
  <simulation name="crawl" duration="3" dt="0.002" control_every="5" solver_iterations="30"
              seed="42" on_controller_error="pause" solver="block_nncg" newton_steps="4">
    <environment file="env.xml"/>
    <robot file="snake.xml" actuation="act.xml"/>
    <record enabled="false" dir="runs/crawl" every="10" flush_seconds="4"/>
  </simulation>
</gaitlab>
)";
    gaitlab::test::write_text(dir / "crawl.xml", xml);
    const gaitlab::SimulationFile from_xml = gaitlab::read_simulation(dir / "crawl.xml");
    LuaFixture lua;
    std::string code = R"(
local w = gaitlab.world{ gravity = {0, 0, -9.81} }
local r = gaitlab.robot.chain{ name = 'snake', modules = 4 }
w:add(r)
r:actuate(gaitlab.actuation{ groups = {
  { joints = 'pitch', controller = { builtin = 'sine', params = { amplitude = 20 } } } } })
sim = gaitlab.simulation{ world = w, name = 'crawl', duration = 3, dt = 0.002,
  control_every = 5, solver_iterations = 30, seed = 42, on_controller_error = 'pause',
  solver = 'block_nncg', newton_steps = 4, record = { enabled = false, dir = 'runs/crawl', every = 10, flush_seconds = 4 } }
assert(sim.name == 'crawl' and sim.duration == 3)
assert(sim:save(OUT))
)";
    code.replace(code.find("OUT"), 3, "'" + (dir / "lua.xml") + "'");
    lua.run(code);
    const gaitlab::SimulationFile from_lua = gaitlab::read_simulation(dir / "lua.xml");
    CHECK(from_lua.name == from_xml.name);
    CHECK(from_lua.duration == from_xml.duration);
    CHECK(from_lua.options.dt == from_xml.options.dt);
    CHECK(from_lua.options.control_every == from_xml.options.control_every);
    CHECK(from_lua.options.solver_iterations == from_xml.options.solver_iterations);
    CHECK(from_lua.options.seed == from_xml.options.seed);
    CHECK(from_lua.options.on_controller_error == from_xml.options.on_controller_error);
    CHECK(from_xml.options.solver == gaitlab::ConstraintSolver::block_nncg);
    CHECK(from_lua.options.solver == from_xml.options.solver);
    CHECK(from_xml.options.newton_steps == 4);
    CHECK(from_lua.options.newton_steps == from_xml.options.newton_steps);
    CHECK(from_lua.record.enabled == from_xml.record.enabled);
    CHECK(from_lua.record.dir == from_xml.record.dir);
    CHECK(from_lua.record.every == from_xml.record.every);
    CHECK(from_lua.record.flush_seconds == from_xml.record.flush_seconds);
    // the parts: the same environment, robot and actuation
    const auto text = [](const std::string& path) { return gaitlab::test::read_text(path); };
    const std::string xml_master = dir / "crawl.xml", lua_master = dir / "lua.xml";
    CHECK(gaitlab::format_environment(
              gaitlab::read_environment(gaitlab::resolve_path(lua_master, from_lua.environment))) ==
          gaitlab::format_environment(
              gaitlab::read_environment(gaitlab::resolve_path(xml_master, from_xml.environment))));
    REQUIRE(from_lua.robots.size() == 1);
    CHECK(gaitlab::format_robot(
              gaitlab::read_robot(gaitlab::resolve_path(lua_master, from_lua.robots[0].robot))) ==
          gaitlab::format_robot(
              gaitlab::read_robot(gaitlab::resolve_path(xml_master, from_xml.robots[0].robot))));
    CHECK(text(gaitlab::resolve_path(lua_master, from_lua.robots[0].actuation)) ==
          gaitlab::format_actuation(gaitlab::read_actuation(
              gaitlab::resolve_path(xml_master, from_xml.robots[0].actuation))));
    // a loaded simulation, saved again (or a copy of it), keeps the file's settings
    LuaFixture again;
    std::string resave = R"(
local sim = gaitlab.simulation.load(IN)
assert(sim.name == 'crawl' and sim.duration == 3)
assert(sim:clone().name == 'crawl')
assert(sim:save(OUT))
)";
    resave.replace(resave.find("IN"), 2, "'" + xml_master + "'");
    resave.replace(resave.find("OUT"), 3, "'" + (dir / "again.xml") + "'");
    again.run(resave);
    const gaitlab::SimulationFile resaved = gaitlab::read_simulation(dir / "again.xml");
    CHECK(resaved.name == "crawl");
    CHECK(resaved.duration == 3);
    CHECK(resaved.record.enabled == from_xml.record.enabled);
    CHECK(resaved.record.every == 10);
    CHECK(resaved.record.flush_seconds == 4);
}

TEST_CASE("the Lua keys of the XML attributes refuse bad values, naming the key", "[xml_lua]") {
    LuaFixture lua;
    const auto bad = [](const char* fn) {
        return std::string("test:1: bad argument #1 to '") + fn + "' (";
    };
    CHECK(lua.error_of("gaitlab.robot.chain{ modules = 2, self_collision = 'yes' }") ==
          bad("chain") + "field 'self_collision': boolean expected, got string)");
    // robots of bodies and joints: the robot file's checks, with the entry and key named
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = {} }") ==
          bad("new") + "field 'bodies': a robot needs at least one body)");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = 3 }") ==
          bad("new") + "field 'bodies': list of tables expected, got number)");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 1, 1} } } }") ==
          bad("new") + "bodies[1]: field 'mass': number expected (kg), got nil)");
    CHECK(lua.error_of(
              "gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 1, 1}, mass = -1 } } }") ==
          bad("new") + "bodies[1]: robot 'robot' body 'a' mass must be positive (got -1 kg))");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 0.001, 0.001}, "
                       "mass = 1 } } }") ==
          bad("new") +
              "bodies[1]: robot 'robot' body 'a' longest side must be at most 300 times its "
              "second longest (got 1 x 0.001 x 0.001 m: 1000 times))");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'a', shape = 'cylinder', size = "
                       "{1, 0.002, 0.002}, mass = 1 } } }") ==
          bad("new") +
              "bodies[1]: robot 'robot' body 'a' length must be at most 300 times its diameter "
              "(got 1 m and 0.002 m: 500 times))");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 1, 1}, mass = 1, "
                       "inertia = {0.1, 0.1, 0.3} } } }") ==
          bad("new") +
              "bodies[1]: robot 'robot' body 'a' inertia must have each moment at most the sum "
              "of the other two, as every body's has (got 0.1 0.1 0.3 kg·m²: z is 0.3, the "
              "other two add up to 0.2))");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 0.5, 0.5}, "
                       "mass = 1, com = {0, 0.3, 0} } } }") ==
          bad("new") +
              "bodies[1]: robot 'robot' body 'a' com must lie inside the box: each coordinate "
              "within half its size, ±0.5 ±0.25 ±0.25 m (got 0 0.3 0 m))");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 1, 1}, mass = 1, "
                       "com = {0, 0/0, 0} } } }") ==
          bad("new") + "bodies[1]: robot 'robot' body 'a' com must be a finite number)");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 1, 1}, mass = 1, "
                       "inertia = 0.1 } } }") ==
          bad("new") + "bodies[1]: field 'inertia': vector expected ({x, y, z}), got number)");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 1, 1}, mass = 1 "
                       "}, { name = 'a', size = {1, 1, 1}, mass = 1 } } }") ==
          bad("new") + "bodies[2]: field 'name': a second body named 'a')");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 1, 1}, mass = 1, "
                       "orientation = {1, 1, 0, 0} } } }") ==
          bad("new") +
              "bodies[1]: field 'orientation': a unit quaternion expected (its norm is "
              "1.4142135623730951))");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'a', size = {1, 1, 1}, mass = 1, "
                       "shape = 'sphere' } } }") ==
          bad("new") + "bodies[1]: field 'shape': 'box' or 'cylinder' expected, got 'sphere')");
    const std::string two =
        "bodies = { { name = 'base', size = {.1, .1, .1}, mass = 1 }, "
        "{ name = 'b', size = {.1, .1, .1}, mass = 1 } }, ";
    CHECK(lua.error_of("gaitlab.robot.new{ " + two +
                       "joints = { { name = 'j', parent = 'base', child = 'bse', pivot = {0, "
                       "0, 0}, axis = {0, 1, 0} } } }") ==
          bad("new") +
              "joints[1]: field 'child': no body 'bse' in the robot; did you mean "
              "'base'?)");
    CHECK(lua.error_of("gaitlab.robot.new{ " + two +
                       "joints = { { name = 'j', parent = 'base', child = 'b', pivot = {0, 0, "
                       "0}, axis = {0, 2, 0} } } }") ==
          bad("new") + "joints[1]: robot 'robot' joint 'j' axis must be a unit vector)");
    CHECK(lua.error_of("gaitlab.robot.new{ " + two +
                       "joints = { { name = 'j', parent = 'base', child = 'b', pivot = {0, 0, "
                       "0}, axis = {0, 1, 0}, role = 'twist' } } }") ==
          bad("new") +
              "joints[1]: field 'role': 'pitch', 'yaw' or 'roll' expected, got "
              "'twist')");
    CHECK(lua.error_of("gaitlab.robot.new{ " + two +
                       "joints = { { name = 'j', parent = 'base', child = 'b', pivot = {0, 0, "
                       "0}, axis = {0, 1, 0}, min = 30, max = -30 } } }") ==
          bad("new") + "joints[1]: robot 'robot' joint 'j' range must have min < max)");
    // the servo's speed in deg/s, as the script gave it, not the engine's rad/s
    CHECK(lua.error_of("gaitlab.robot.new{ " + two +
                       "joints = { { name = 'j', parent = 'base', child = 'b', pivot = {0, 0, "
                       "0}, axis = {0, 1, 0}, max_speed = 1e6 } } }") ==
          bad("new") +
              "joints[1]: field 'max_speed': must be in (0, 57295.77951308232] deg/s (got "
              "1000000 deg/s))");
    CHECK(lua.error_of("gaitlab.module{ name = 'mm', range = {1, 2}, min = 3 }") ==
          bad("module") + "field 'min': give range or min and max, not both)");
    // environments
    CHECK(lua.error_of("gaitlab.world{ floor = { enabled = 1 } }") ==
          bad("world") + "field 'enabled': boolean expected, got number)");
    lua.run("w = gaitlab.world{}");
    const std::string box = "test:1: bad argument #1 to 'box' (";
    CHECK(lua.error_of("w:box{ yaw = 10, orientation = {1, 0, 0, 0} }") ==
          box + "field 'orientation': give 'yaw' or 'orientation', not both)");
    CHECK(lua.error_of("w:box{ orientation = {1, 0, 0} }") ==
          box + "field 'orientation': unit quaternion expected ({w, x, y, z} with four numbers))");
    CHECK(lua.error_of("w:box{ orientation = {2, 0, 0, 0} }") ==
          box + "field 'orientation': a unit quaternion expected (its norm is 2))");
    const std::string place = "test:1: bad argument #1 to 'place' (";
    CHECK(lua.error_of("w:place{ position = {0, 0, 0} }") ==
          place + "field 'robot': robot name expected, got nil)");
    CHECK(lua.error_of("w:place{ robot = 'x' } w:place{ robot = 'x' }") ==
          place + "field 'robot': robot 'x' is placed twice)");
    // a name is checked as a robot's: a zero byte would be cut where the file is written
    CHECK(lua.error_of("w:place{ robot = 'snake\\0x' }") ==
          place +
              "field 'robot': robot name must be valid UTF-8 without control characters "
              "(got \"snake\\x00x\"))");
    // simulations
    CHECK(lua.error_of("gaitlab.simulation{ world = w, name = '' }") ==
          bad("simulation") + "field 'name': a non-empty name expected)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, name = 'walk\\0x' }") ==
          bad("simulation") +
              "field 'name': simulation name must be valid UTF-8 without "
              "control characters (got \"walk\\x00x\"))");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, duration = -1 }") ==
          bad("simulation") + "field 'duration': non-negative number of seconds expected)");
    CHECK(lua.error_of("gaitlab.simulation{ world = w, record = { every = -1 } }") ==
          bad("simulation") + "field 'record': every must be in [0, 1000000] (got -1))");
    CHECK(
        lua.error_of("gaitlab.simulation{ world = w, record = { every = 2, record_every = 3 } }") ==
        bad("simulation") +
            "field 'record': field 'every': give 'every' or 'record_every', not both)");
    // actuations: the actuation file's checks of a group's joints
    const std::string act = bad("actuation") + "groups[1]: field ";
    CHECK(lua.error_of("gaitlab.actuation{ groups = { { joints = 'roll', controller = { builtin "
                       "= 'sine' } } } }") ==
          act +
              "'joints': 'pitch', 'yaw', 'all' or joint numbers (from 1) expected, got "
              "'roll')");
    CHECK(lua.error_of("gaitlab.actuation{ groups = { { joints = {1, 1}, controller = { "
                       "builtin = 'sine' } } } }") == act + "'joints': joint 1 is listed twice)");
    CHECK(lua.error_of("gaitlab.actuation{ groups = { { joints = 'all', controller = { builtin "
                       "= 'sine', template = 'x' } } } }") ==
          act +
              "'controller': exactly one of 'builtin', 'file' or 'template' expected (which "
              "controller))");
    CHECK(lua.error_of("gaitlab.actuation{ groups = { { joints = 'all', controller = { builtin "
                       "= 'sine', params = { amplitude = 'big' } } } } }") ==
          act + "'controller': params: 'amplitude' must be a number, got string)");
    CHECK(lua.error_of("gaitlab.actuation{ groups = { { joints = 'all' } } }") ==
          act +
              "'controller': table expected ({ builtin|file|template = name, params = {...} "
              "}), got nil)");
    // parameter names are checked when a robot is driven, as for a file
    CHECK(lua.error_of("gaitlab.robot.chain{ modules = 2 }:actuate(gaitlab.actuation{ groups = "
                       "{ { joints = 'all', controller = { builtin = 'sine', params = { "
                       "amplitud = 1 } } } } })") ==
          "test:1: bad argument #1 to 'actuate' (controller 'sine' has no parameter 'amplitud'; "
          "did you mean 'amplitude'? (parameters: amplitude, frequency, phase, phase0, offset))");
}
