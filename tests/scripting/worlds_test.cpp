// The ready-made worlds (worlds/*.lua) and the preset machinery that loads them
// (stdlib/worlds.lua): every world takes a robot at its start and simulates it, parameters are
// checked, and world files load from disk too.
#include <catch2/catch.hpp>

#include "lua_fixture.h"

using gaitlab::test::LuaFixture;

namespace {

// Lua helpers: the corners of a robot body (a box) in the world frame, and the lowest clearance
// of a robot's corners above a surface function
const char* kHelpers = R"(
function corners(b)
  local q, s, p = b.orientation, b.size, b.position
  local out = {}
  for _, sx in ipairs{ -1, 1 } do for _, sy in ipairs{ -1, 1 } do for _, sz in ipairs{ -1, 1 } do
    local x, y, z = sx * s.x / 2, sy * s.y / 2, sz * s.z / 2
    -- rotate (x, y, z) by the unit quaternion q
    local tx = 2 * (q.y * z - q.z * y)
    local ty = 2 * (q.z * x - q.x * z)
    local tz = 2 * (q.x * y - q.y * x)
    out[#out + 1] = {
      x = p.x + x + q.w * tx + (q.y * tz - q.z * ty),
      y = p.y + y + q.w * ty + (q.z * tx - q.x * tz),
      z = p.z + z + q.w * tz + (q.x * ty - q.y * tx),
    }
  end end end
  return out
end

function clearance(robot, surface)
  local least = math.huge
  for _, b in ipairs(robot:bodies()) do
    for _, c in ipairs(corners(b)) do least = math.min(least, c.z - surface(c.x, c.y)) end
  end
  return least
end

-- places an 8-module snake at the world's start and runs a head-first sine gait (the
-- simulation is kept in the global `sim`, so the robot stays in it)
function run_in(world, start, seconds, module)
  local robot = gaitlab.robot.chain{ name = "snake", modules = 8, module = module }
  world:add(robot, start)
  robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5,
                                                       phase = -120 })
  sim = gaitlab.simulation{ world = world }
  sim:run(seconds)
  return robot, sim
end
)";

}  // namespace

TEST_CASE("every ready-made world is there", "[worlds]") {
    LuaFixture lua;
    lua.run(R"(
        names = {}
        for name, preset in pairs(gaitlab.worlds) do
          names[#names + 1] = name
          assert(preset.name == name and #preset.description > 0)
        end
        table.sort(names)
        names = table.concat(names, " ")
    )");
    CHECK(lua.string("names") == "flat hills pipe ramp rubble slippery stairs sticky");
    CHECK(lua.string("tostring(gaitlab.worlds.ramp)") == "gaitlab.WorldPreset 'ramp'");
    CHECK(lua.number("gaitlab.worlds.ramp.params.slope[1]") == 10);
    CHECK(lua.string("gaitlab.worlds.ramp.params.slope.unit") == "deg");
}

TEST_CASE("a snake placed in each flat world stays on the floor", "[worlds]") {
    const char* name = GENERATE("flat", "slippery", "sticky");
    CAPTURE(name);
    LuaFixture lua;
    lua.run(kHelpers);
    lua.run(std::string("world, start = gaitlab.worlds.") + name + "()");
    lua.run("robot = run_in(world, start, 2)");
    CHECK(lua.number("clearance(robot, function() return 0 end)") > -0.002);
    // it moved head first, a few centimetres
    CHECK(lua.number("robot:displacement().x") > 0.01);
}

TEST_CASE("the flat worlds differ only in friction", "[worlds]") {
    LuaFixture lua;
    lua.run(R"lua(
        ok = true
        for _, name in ipairs{ "flat", "slippery", "sticky" } do
          local w = gaitlab.worlds[name]{ friction = 0.5 }
          ok = ok and tostring(w) == "gaitlab.World (0 robots, 0 boxes)"
        end
    )lua");
    CHECK(lua.boolean("ok"));
    CHECK(lua.number("gaitlab.worlds.flat.params.friction[1]") == 0.8);
    CHECK(lua.number("gaitlab.worlds.slippery.params.friction[1]") == 0.1);
    CHECK(lua.number("gaitlab.worlds.sticky.params.friction[1]") == 1.0);
}

TEST_CASE("a snake on the ramp lies on the slope and stays above it", "[worlds]") {
    LuaFixture lua;
    lua.run(kHelpers);
    lua.run(R"(
        world, start = gaitlab.worlds.ramp{ slope = 15 }
        t = math.tan(math.rad(15))
        function ramp(x) return math.max(0, math.min(x, 1.0)) * t end
        robot, sim = run_in(world, start, 0)
        at_start = clearance(robot, ramp)
        sim:run(2)
    )");
    // it starts lying on the slope, not floating or buried
    CHECK(lua.number("at_start") == Approx(0.001).margin(0.001));
    CHECK(lua.number("clearance(robot, ramp)") > -0.003);
    CHECK(lua.number("robot:position().z") > 0.1);
}

TEST_CASE("the stairs preset builds the steps asked for, in front of the snake", "[worlds]") {
    LuaFixture lua;
    lua.run(kHelpers);
    lua.run(R"(
        world, start = gaitlab.worlds.stairs{ steps = 4, step_height = 0.03 }
        top = 0
        for _, solid in ipairs(world:triangles()) do
          for i = 3, #solid.vertices, 3 do top = math.max(top, solid.vertices[i]) end
        end
        function stairs(x)
          return math.max(0, math.min(4, math.floor((x - 0.7) / 0.25) + 1)) * 0.03
        end
        robot = run_in(world, start, 2)
    )");
    CHECK(lua.number("top") == Approx(0.12));
    CHECK(lua.number("clearance(robot, stairs)") > -0.002);
}

TEST_CASE("a snake in the pipe stays inside it", "[worlds]") {
    // the y1 snake, and a snake of 60 mm cube modules (the largest the start fits)
    const char* module = GENERATE("y1", "cube");
    CAPTURE(module);
    LuaFixture lua;
    lua.run(kHelpers);
    lua.run(std::string("module = '") + module + "'");
    lua.run(R"(
        world, start = gaitlab.worlds.pipe()
        robot = run_in(world, start, 2, module)
        outside, behind, beyond = 0, math.huge, -math.huge
        for _, b in ipairs(robot:bodies()) do
          for _, c in ipairs(corners(b)) do
            -- the axis is at y = 0, z = radius + thickness = 0.09
            outside = math.max(outside, math.sqrt(c.y ^ 2 + (c.z - 0.09) ^ 2) - 0.08)
            behind, beyond = math.min(behind, c.x), math.max(beyond, c.x)
          end
        end
    )");
    CHECK(lua.number("outside") < 0.002);
    CHECK(lua.number("behind") > -0.2);
    CHECK(lua.number("beyond") < 1.3);
    CHECK(lua.number("robot:displacement().x") > 0.01);
}

TEST_CASE("a snake on the rubble stays above the floor and is the same for the same seed",
          "[worlds]") {
    LuaFixture lua;
    lua.run(kHelpers);
    lua.run(R"(
        function final(seed)
          local world, start = gaitlab.worlds.rubble{ seed = seed }
          local robot = run_in(world, start, 2)
          return robot:position(), clearance(robot, function() return 0 end)
        end
        a, ca = final(1)
        b = final(1)
        c = final(2)
    )");
    CHECK(lua.number("ca") > -0.002);
    CHECK(lua.boolean("a == b"));        // bit-identical
    CHECK_FALSE(lua.boolean("a == c"));  // other stones, another outcome
}

TEST_CASE("rubble fields with the same seed are identical, with another seed they differ",
          "[worlds]") {
    LuaFixture lua;
    lua.run(R"(
        function stones(seed)
          local out = {}
          for _, solid in ipairs(gaitlab.worlds.rubble{ seed = seed, count = 30 }:triangles()) do
            out[#out + 1] = table.concat(solid.vertices, " ")
          end
          return table.concat(out, "\n")
        end
        n = #gaitlab.worlds.rubble{ count = 30 }:triangles()
    )");
    CHECK(lua.integer("n") == 30);
    CHECK(lua.boolean("stones(5) == stones(5)"));
    CHECK_FALSE(lua.boolean("stones(5) == stones(6)"));
}

TEST_CASE("a snake on the hills rests on the terrain", "[worlds]") {
    LuaFixture lua;
    lua.run(kHelpers);
    lua.run(R"(
        world, start = gaitlab.worlds.hills()
        k = 2 * math.pi / 0.8
        function hills(x, y) return 0.02 * (1 - math.cos(k * x) * math.cos(k * y)) end
        robot = run_in(world, start, 2)
        low = clearance(robot, hills)
    )");
    // the terrain is sampled every 2 cm and its triangles cut the curve's corners
    CHECK(lua.number("low") > -0.003);
    CHECK(lua.number("low") < 0.01);  // it came down onto the terrain
}

TEST_CASE("preset parameters are checked like any Lua argument", "[worlds]") {
    LuaFixture lua;
    const std::string bad = "test:1: bad argument #1 to 'ramp' (";
    CHECK(lua.error_of("gaitlab.worlds.ramp{ slop = 5 }") ==
          bad +
              "unknown key 'slop'; did you mean 'slope'? (parameters of 'ramp': friction, "
              "length, slope, top, width))");
    CHECK(lua.error_of("gaitlab.worlds.ramp{ slope = 60 }") ==
          bad + "slope must be in [1, 45] deg (got 60))");
    CHECK(lua.error_of("gaitlab.worlds.ramp{ friction = -1 }") ==
          bad + "friction must be in [0, 1] (got -1))");
    CHECK(lua.error_of("gaitlab.worlds.ramp{ slope = 'steep' }") ==
          bad + "field 'slope': number expected, got string)");
    CHECK(lua.error_of("gaitlab.worlds.ramp(5)") == bad + "table expected, got number)");
    CHECK(lua.error_of("gaitlab.worlds.ramp{ 10 }") ==
          bad + "unexpected number key (fields are named))");
    CHECK(lua.error_of("gaitlab.worlds.stairs{ steps = 2.5 }") ==
          "test:1: bad argument #1 to 'stairs' (field 'steps': integer expected, got a "
          "fractional number)");
    CHECK(lua.error_of("gaitlab.worlds.ramp{ slope = 0/0 }") ==
          bad + "slope must be in [1, 45] deg (got nan))");
    // a check across parameters
    CHECK(lua.error_of("gaitlab.worlds.rubble{ min_size = 0.1 }") ==
          "test:1: bad argument #1 to 'rubble' (max_size must not be below min_size (got 0.06 < "
          "0.1 m))");
    // integers given as floats are accepted
    lua.run("w = gaitlab.worlds.stairs{ steps = 2.0 }");
    CHECK(lua.integer("#w:triangles()") == 2);
}

TEST_CASE("gaitlab.world.load runs a world file relative to the calling script", "[worlds]") {
    LuaFixture lua;
    const std::string dir = gaitlab::test::lua_dir() + "/worlds";
    // the embedded ramp and worlds/ramp.lua on disk are the same preset
    lua.run("ramp = gaitlab.world.load('" GAITLAB_SOURCE_DIR "/worlds/ramp.lua')");
    CHECK(lua.string("tostring(ramp)") == "gaitlab.WorldPreset 'ramp'");
    CHECK(lua.string("tostring(ramp{ slope = 20 })") == "gaitlab.World (0 robots, 1 box, 1 ramp)");
    // a world file of the user's, loaded from a script next to it
    lua.run("dofile('" + dir + "/uses_corridor.lua')");
    CHECK(lua.string("tostring(corridor_world)") ==
          "gaitlab.World (0 robots, 0 boxes, 2 walls, 1 cylinder)");
    CHECK(lua.number("corridor_start.x") == -0.5);

    CHECK(lua.error_of("gaitlab.world.load('" + dir + "/nothing_here.lua')") ==
          "test:1: cannot load world '" + dir + "/nothing_here.lua': cannot read " + dir +
              "/nothing_here.lua: No such file or directory");
    // a directory, a device or a FIFO is refused up front, never read (a FIFO would block)
    CHECK(lua.error_of("gaitlab.world.load('" + dir + "')") ==
          "test:1: cannot load world '" + dir + "': cannot read " + dir + ": is a directory");
    CHECK(lua.error_of("gaitlab.world.load('/dev/zero')") ==
          "test:1: cannot load world '/dev/zero': cannot read /dev/zero: not a regular file (a "
          "FIFO, device or socket)");
    CHECK(lua.error_of("gaitlab.world.load('" + dir + "/not_a_world.lua')") ==
          "test:1: " + dir +
              "/not_a_world.lua: a world file must return "
              "gaitlab.world.preset{...}, got table");
    CHECK(lua.error_of("gaitlab.world.load(3)") ==
          "test:1: bad argument #1 to 'load' (string expected, got number)");
}

TEST_CASE("gaitlab.world.preset checks its definition", "[worlds]") {
    LuaFixture lua;
    const std::string bad = "test:1: bad argument #1 to 'preset' (";
    CHECK(lua.error_of("gaitlab.world.preset{ name = 'x' }") ==
          bad + "field 'build': function expected, got nil)");
    CHECK(lua.error_of("gaitlab.world.preset{ name = 'x', biuld = print }") ==
          bad + "unknown key 'biuld'; did you mean 'build'?)");
    CHECK(lua.error_of("gaitlab.world.preset{ name = 'x', build = print, params = "
                       "{ a = { 5, min = 0, max = 1 } } }") ==
          bad + "params.a: numbers min <= default <= max expected)");
    CHECK(lua.error_of("gaitlab.world.preset{ name = 'x', build = print, params = "
                       "{ a = { 0.5, min = 0, max = 1, units = 'm' } } }") ==
          bad + "params.a: unknown key 'units'; did you mean 'unit'?)");
    lua.run("p = gaitlab.world.preset{ name = 'broken', build = function() return 42 end }");
    CHECK(lua.error_of("p()") ==
          "test:1: world preset 'broken': build must return a gaitlab.World, got number");
}
