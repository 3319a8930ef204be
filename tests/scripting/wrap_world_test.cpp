// gaitlab.world: floor, gravity, boxes and placing robots (scripting/src/wrap_world.cpp).
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::test::LuaFixture;

TEST_CASE("world rejects bad arguments with Lua-worded messages", "[wrap_world]") {
    LuaFixture lua;
    const std::string bad = "test:1: bad argument #1 to 'world' (";
    CHECK(lua.error_of("gaitlab.world{ floor = { friction = 1.5 } }") ==
          bad + "floor friction must be in [0, 1] (got 1.5))");
    CHECK(lua.error_of("gaitlab.world{ floor = { friction = -0.1 } }") ==
          bad + "floor friction must be in [0, 1] (got -0.1))");
    CHECK(lua.error_of("gaitlab.world{ floor = { friction = 'high' } }") ==
          bad + "field 'friction': number expected, got string)");
    CHECK(lua.error_of("gaitlab.world{ floor = { frction = 0.5 } }") ==
          bad + "unknown key 'frction'; did you mean 'friction'?)");
    CHECK(lua.error_of("gaitlab.world{ floor = 3 }") ==
          bad + "field 'floor': table or boolean expected, got number)");
    CHECK(lua.error_of("gaitlab.world{ gravity = 9.81 }") ==
          bad + "field 'gravity': vector expected ({x, y, z}), got number)");
    CHECK(lua.error_of("gaitlab.world{ gravity = { 0, 0 } }") ==
          bad + "field 'gravity': vector expected ({x, y, z} with three numbers))");
    CHECK(lua.error_of("gaitlab.world{ gravty = { 0, 0, -1 } }") ==
          bad + "unknown key 'gravty'; did you mean 'gravity'?)");
    CHECK(lua.error_of("gaitlab.world(5)") == bad + "table expected, got number)");
}

TEST_CASE("the floor takes a stiffness and a damping, or rigid = true and neither",
          "[wrap_world]") {
    LuaFixture lua;
    const std::string bad = "test:1: bad argument #1 to 'world' (";
    CHECK(lua.error_of("gaitlab.world{ floor = { rigid = true, stiffness = 1e4 } }") ==
          bad +
              "a rigid floor takes no stiffness (a floor is rigid, or compliant with a "
              "stiffness and a damping))");
    CHECK(lua.error_of("gaitlab.world{ floor = { friction = 0.5, rigid = true, damping = 20 } }") ==
          bad +
              "a rigid floor takes no damping (a floor is rigid, or compliant with a stiffness "
              "and a damping))");
    CHECK(lua.error_of("gaitlab.world{ floor = { rigid = 'yes' } }") ==
          bad + "field 'rigid': boolean expected, got string)");
    lua.run("gaitlab.world{ floor = { stiffness = 1e4 } }");
    lua.run("gaitlab.world{ floor = { damping = 20 } }");
    lua.run("gaitlab.world{ floor = { rigid = false, stiffness = 1e4, damping = 20 } }");
    CHECK(lua.error_of("gaitlab.world{ floor = { stiffness = 0, damping = 20 } }") ==
          bad + "floor stiffness must be positive (got 0 N/m))");
    CHECK(lua.error_of("gaitlab.world{ floor = { stiffness = 1/0, damping = 20 } }") ==
          bad + "floor stiffness must be positive (got inf N/m))");
    CHECK(lua.error_of("gaitlab.world{ floor = { stiffness = 1e4, damping = -2 } }") ==
          bad + "floor damping must not be negative (got -2 N·s/m))");
    CHECK(lua.error_of("gaitlab.world{ floor = { stiffness = 'hard', damping = 20 } }") ==
          bad + "field 'stiffness': number expected, got string)");
    CHECK(lua.error_of("gaitlab.world{ floor = { stiffness = 1e4, damping = {} } }") ==
          bad + "field 'damping': number expected, got table)");
    CHECK(lua.error_of("gaitlab.world{ floor = { stifness = 1e4, damping = 20 } }") ==
          bad + "unknown key 'stifness'; did you mean 'stiffness'?)");
    lua.run("w = gaitlab.world{ floor = { friction = 0.8, stiffness = 1e4, damping = 0 } }");
}

TEST_CASE("a robot rests lower on a compliant floor, the same each run, and the floor saves",
          "[wrap_world]") {
    gaitlab::test::TempDir dir("soft_floor");
    LuaFixture lua;
    lua.run("DIR = '" + dir.str() + "'");
    lua.run(R"(
        -- a 4-module chain at rest after 1 s on a world of `floor` (or on `world` as given):
        -- its height, its position to the bit, and the world
        function rest(floor, world)
          local r = gaitlab.robot.chain{ name = "r", modules = 4 }
          local w = world or gaitlab.world{ floor = floor }
          w:add(r)
          local sim = gaitlab.simulation{ world = w }
          sim:run(1)
          local p = r:position()
          return p.z, string.format("%a %a %a", p.x, p.y, p.z), w
        end
        -- the same on the world saved to FILE and loaded back
        function rest_saved(world, file)
          assert(world:save(DIR .. "/" .. file))
          return rest(nil, assert(gaitlab.world.load(DIR .. "/" .. file)))
        end
        rigid, _, rigid_world = rest({ friction = 0.8, rigid = true })
        rigid_again = rest_saved(rigid_world, "rigid.xml")
        soft, bits1, world = rest({ friction = 0.8, stiffness = 1e4, damping = 20 })
        soft2, bits2 = rest({ friction = 0.8, stiffness = 1e4, damping = 20 })
        stiff = rest({ friction = 0.8, stiffness = 1e5, damping = 20 })
        by_default, bits_default, default_world = rest({ friction = 0.8 })
        _, bits_given = rest({ friction = 0.8, stiffness = 3e3, damping = 60 })
        _, bits_default_loaded = rest_saved(default_world, "default.xml")
        _, bits3 = rest_saved(world, "soft.xml")
    )");
    // 200 g on 20 corner points of k = 1e4 N/m: about 10 µm
    CHECK(lua.number("rigid - soft") == Approx(1e-5).epsilon(0.1));
    CHECK(lua.number("rigid - stiff") == Approx(1e-6).epsilon(0.1));
    CHECK(lua.boolean("bits1 == bits2"));
    // the default floor is 3e3 N/m and 60 N·s/m, and saves as such (about 33 µm)
    CHECK(lua.number("rigid - by_default") == Approx(3.3e-5).epsilon(0.1));
    CHECK(lua.boolean("bits_default == bits_given"));
    CHECK(lua.boolean("bits_default_loaded == bits_default"));
    CHECK(lua.boolean("rigid_again == rigid"));
    // the saved world is the same world: the same run, bit for bit
    CHECK(lua.boolean("bits3 == bits1"));
    std::ifstream in(dir.file("soft.xml"));
    std::stringstream text;
    text << in.rdbuf();
    CHECK(text.str().find("<floor friction=\"0.8\" stiffness=\"10000\" damping=\"20\"/>") !=
          std::string::npos);
}

TEST_CASE("world:box checks its fields", "[wrap_world]") {
    LuaFixture lua;
    lua.run("w = gaitlab.world()");
    const std::string bad = "test:1: bad argument #1 to 'box' (";
    CHECK(lua.error_of("w:box{ size = { 1, 1, 1 }, mass = -1 }") ==
          bad + "box 1 mass must not be negative (got -1 kg))");
    CHECK(lua.error_of("w:box{ size = { 0, 1, 1 } }") ==
          bad + "box 1 size x must be positive (got 0 m))");
    CHECK(lua.error_of("w:box{ friction = 2 }") ==
          bad + "box 1 friction must be in [0, 1] (got 2))");
    CHECK(lua.error_of("w:box{ size = { 1, 0.001, 0.001 }, mass = 1 }") ==
          bad +
              "box 1 longest side must be at most 300 times its second longest (got 1 x 0.001 "
              "x 0.001 m: 1000 times; a static box, of mass 0, may be more slender))");
    CHECK(lua.error_of("w:box{ sise = { 1, 1, 1 } }") ==
          bad + "unknown key 'sise'; did you mean 'size'?)");
    CHECK(lua.error_of("w:box()") == bad + "table expected, got no value)");
    CHECK(lua.error_of("w:box{ yaw = 0/0 }") == bad + "box 1 yaw must be a finite number)");
    // a valid box returns the world, so calls chain
    CHECK(lua.string("tostring(w:box{ size = { 1, 1, 0.1 } }:box{ mass = 1 })") ==
          "gaitlab.World (0 robots, 2 boxes)");
}

TEST_CASE("a vector or a quaternion with a number or a key too many is refused, naming the field",
          "[wrap_world]") {
    LuaFixture lua;
    lua.run("w = gaitlab.world()");
    const std::string bad = "test:1: bad argument #1 to 'box' (";
    // these used to be accepted, the fourth number or the key 'w' dropped
    CHECK(lua.error_of("w:box{ size = { 0.1, 0.1, 0.1, 0.1 } }") ==
          bad + "field 'size': 3 numbers expected ({x, y, z}), got 4)");
    CHECK(lua.error_of("w:box{ position = { x = 1, y = 2, z = 3, w = 4 } }") ==
          bad + "field 'position': unknown key 'w' (a vector's keys are x, y and z))");
    // of several unknown keys the first in byte order, the same in every run
    CHECK(lua.error_of("w:box{ position = { x = 1, y = 2, z = 3, zz = 1, b = 2, a = 3 } }") ==
          bad + "field 'position': unknown key 'a' (a vector's keys are x, y and z))");
    CHECK(lua.error_of("w:box{ position = { 1, 2, 3, [10] = 4 } }") ==
          bad + "field 'position': 3 numbers expected ({x, y, z}), got 4)");
    CHECK(lua.error_of("w:box{ position = { [0] = 1, 1, 2, 3 } }") ==
          bad + "field 'position': 3 numbers expected ({x, y, z}), got 4)");
    CHECK(lua.error_of("w:box{ position = { 1, x = 2, 0, 0 } }") ==
          bad + "field 'position': x given twice: by name and as number 1 of {x, y, z})");
    CHECK(lua.error_of("w:box{ orientation = { 1, 0, 0, 0, 0 } }") ==
          bad + "field 'orientation': 4 numbers expected ({w, x, y, z}), got 5)");
    CHECK(lua.error_of("w:box{ orientation = { w = 1, x = 0, y = 0, z = 0, s = 1 } }") ==
          bad +
              "field 'orientation': unknown key 's' (a unit quaternion's keys are w, x, y and "
              "z))");
    CHECK(lua.error_of("gaitlab.world{ gravity = { 0, 0, -9.81, 0 } }") ==
          "test:1: bad argument #1 to 'world' (field 'gravity': 3 numbers expected ({x, y, z}), "
          "got 4)");
    // every other reader of vectors: sensor directions, bodies and joints
    lua.run("r = gaitlab.robot.chain{ name = 'snake', modules = 2 }");
    CHECK(lua.error_of("r:sensor{ kind = 'range', module = 1, direction = { 0, 0, -1, 0 } }") ==
          "test:1: bad argument #1 to 'sensor' (field 'direction': 3 numbers expected ({x, y, "
          "z}), got 4)");
    CHECK(lua.error_of("gaitlab.robot.new{ bodies = { { name = 'b', size = { 0.1, 0.1, 0.1 }, "
                       "mass = 1, position = { x = 0, y = 0, z = 0, t = 0 } } } }") ==
          "test:1: bad argument #1 to 'new' (bodies[1]: field 'position': unknown key 't' (a "
          "vector's keys are x, y and z))");
    // the forms that were valid still are: three numbers, x y z keys, a gaitlab.Vec3, a
    // quaternion {w, x, y, z} by place or by name
    lua.run(R"(
        w:box{ size = { 0.1, 0.2, 0.3 }, position = { x = 1, y = 2, z = 3 } }
        w:box{ position = gaitlab.vec3(1, 2, 0.5), orientation = { w = 1, x = 0, y = 0, z = 0 } }
        w:box{ position = { 1, 2, z = 3 }, orientation = { 1, 0, 0, 0 } }
    )");
    CHECK(lua.string("tostring(w)") == "gaitlab.World (0 robots, 3 boxes)");
}

TEST_CASE("world:add places a robot once", "[wrap_world]") {
    LuaFixture lua;
    lua.run("w = gaitlab.world() r = gaitlab.robot.chain{ name = 'a', modules = 2 }");
    CHECK(lua.error_of("w:add(42)") ==
          "test:1: bad argument #1 to 'add' (gaitlab.Robot expected, got number)");
    CHECK(lua.error_of("w:add(r, { x = 1, yew = 90 })") ==
          "test:1: bad argument #2 to 'add' (unknown key 'yew'; did you mean 'yaw'?)");
    lua.run("same = w:add(r, { x = 1, y = 2, yaw = 90 }) == w");
    CHECK(lua.boolean("same"));
    CHECK(lua.error_of("w:add(r)") ==
          "test:1: bad argument #1 to 'add' (robot 'a' is already in a world)");
    // yaw 90 turns the chain to lie along +y from (1, 2)
    lua.run("sim = gaitlab.simulation{ world = w } p = r:bodies()[3].position");
    CHECK(lua.number("p.x") == Approx(1).margin(1e-9));
    CHECK(lua.number("p.y") == Approx(2 + 0.126).margin(1e-9));
}

TEST_CASE("gravity and floor options change what happens", "[wrap_world]") {
    LuaFixture lua;
    lua.run(R"(
        r1 = gaitlab.robot.chain{ modules = 2 }
        w1 = gaitlab.world{ floor = false }
        w1:add(r1, { z = 1 })
        s1 = gaitlab.simulation{ world = w1 }
        s1:run(0.2)
        r2 = gaitlab.robot.chain{ modules = 2 }
        w2 = gaitlab.world{ floor = false, gravity = { x = 0, y = 0, z = 0 } }
        w2:add(r2, { z = 1 })
        s2 = gaitlab.simulation{ world = w2 }
        s2:run(0.2)
    )");
    // free fall without a floor: 9.81 · 0.2² / 2 = 0.196 m
    CHECK(lua.number("r1:displacement().z") == Approx(-0.1962).margin(2e-3));
    CHECK(lua.number("r2:displacement():norm()") == Approx(0).margin(1e-9));
}

TEST_CASE("world library methods check their fields and name the object", "[wrap_world]") {
    LuaFixture lua;
    lua.run("w = gaitlab.world()");
    auto bad = [](const char* fn) {
        return std::string("test:1: bad argument #1 to '") + fn + "' (";
    };
    CHECK(lua.error_of("w:wall{ height = -0.1 }") ==
          bad("wall") + "wall 1 height must be positive (got -0.1 m))");
    CHECK(lua.error_of("w:wall{ lenght = 2 }") ==
          bad("wall") + "unknown key 'lenght'; did you mean 'length'?)");
    CHECK(lua.error_of("w:ramp{ slope = 95 }") ==
          bad("ramp") + "ramp 1 slope must be between 0 and 90 deg, both excluded (got 95 deg))");
    CHECK(lua.error_of("w:ramp{ slop = 5 }") ==
          bad("ramp") + "unknown key 'slop'; did you mean 'slope'?)");
    CHECK(lua.error_of("w:ramp{ friction = 1.5 }") ==
          bad("ramp") + "ramp 1 friction must be in [0, 1] (got 1.5))");
    lua.run("w:stairs{} w:stairs{}");
    CHECK(lua.error_of("w:stairs{ step_height = -0.01 }") ==
          bad("stairs") + "stairs 3 step_height must be positive (got -0.01 m))");
    CHECK(lua.error_of("w:stairs{ steps = 2.5 }") ==
          bad("stairs") + "field 'steps': integer expected, got a fractional number)");
    CHECK(lua.error_of("w:stairs{ step_heigth = 0.01 }") ==
          bad("stairs") + "unknown key 'step_heigth'; did you mean 'step_height'?)");
    CHECK(lua.error_of("w:cylinder{ mass = -1 }") ==
          bad("cylinder") + "cylinder 1 mass must not be negative (got -1 kg))");
    CHECK(lua.error_of("w:cylinder{ lying = 'yes' }") ==
          bad("cylinder") + "field 'lying': boolean expected, got string)");
    CHECK(lua.error_of("w:cylinder{ radius = 0.001, length = 1, mass = 1 }") ==
          bad("cylinder") +
              "cylinder 1 length must be at most 300 times its diameter (got 1 m and 0.002 m: "
              "500 times; a static cylinder, of mass 0, may be more slender))");
    CHECK(lua.error_of("w:pipe{ sides = 2 }") ==
          bad("pipe") + "pipe 1 sides must be in [3, 256] (got 2))");
    CHECK(lua.error_of("w:pipe{ radius = 0 }") ==
          bad("pipe") + "pipe 1 radius must be positive (got 0 m))");
    CHECK(lua.error_of("w:rubble{ min_size = 0.1 }") ==
          bad("rubble") + "rubble 1 max_size must not be below min_size (got 0.06 < 0.1 m))");
    CHECK(lua.error_of("w:rubble{ seed = -1 }") ==
          bad("rubble") + "field 'seed': non-negative integer expected)");
    CHECK(lua.error_of("w:rubble{ friction = -0.1 }") ==
          bad("rubble") + "rubble 1 friction must be in [0, 1] (got -0.1))");
    CHECK(lua.error_of("w:rubble{ position = 3 }") ==
          bad("rubble") + "field 'position': vector expected ({x, y, z}), got number)");
    // nothing was added by the failed calls
    CHECK(lua.string("tostring(w)") == "gaitlab.World (0 robots, 0 boxes, 2 stairs)");
    lua.run("w:wall{}:ramp{}:cylinder{}:pipe{}:rubble{}");
    CHECK(lua.string("tostring(w)") ==
          "gaitlab.World (0 robots, 0 boxes, 1 wall, 1 ramp, 2 stairs, 1 cylinder, 1 pipe, "
          "1 rubble field)");
}

TEST_CASE("world:heightfield samples a function, takes rows, or reads an image", "[wrap_world]") {
    LuaFixture lua;
    lua.run(R"(
        w = gaitlab.world()
        calls = 0
        w:heightfield{ length = 1, width = 0.5, samples = { 11, 6 },
                       heights = function(x, y) calls = calls + 1 return x + 10 * y end }
        t = w:triangles()[1]
    )");
    // 11 x 6 samples, 10 x 5 cells of two triangles
    CHECK(lua.integer("calls") == 66);
    CHECK(lua.string("t.kind") == "heightfield");
    CHECK(lua.string("t.object") == "heightfield 1");
    CHECK(lua.integer("#t.vertices") == 10 * 5 * 2 * 9);
    // the function is called in the field's frame, centred on it: every vertex has z = x + 10 y
    lua.run(R"(
        worst = 0
        for i = 1, #t.vertices, 3 do
          local x, y, z = t.vertices[i], t.vertices[i + 1], t.vertices[i + 2]
          worst = math.max(worst, math.abs(z - (x + 10 * y)))
        end
    )");
    CHECK(lua.number("worst") < 1e-12);
    // resolution: 0.25 m over 1 m gives 5 samples
    lua.run(
        "n = 0 w:heightfield{ resolution = 0.25, heights = function() n = n + 1 return 0 end }");
    CHECK(lua.integer("n") == 25);
    // rows: row 1 at y = -width/2
    lua.run("w:heightfield{ length = 2, width = 2, heights = { { 0, 0, 0 }, { 1, 1, 1 } } }");
    lua.run("t3 = w:triangles()[3].vertices");
    CHECK(lua.integer("#t3") == 2 * 2 * 9);

    const std::string bad = "test:1: bad argument #1 to 'heightfield' (";
    CHECK(lua.error_of("w:heightfield{}") ==
          bad +
              "field 'heights': give either heights (a function or a table of rows) or an "
              "image)");
    CHECK(lua.error_of("w:heightfield{ heights = {{0, 0}, {0, 0}}, image = 'a.png' }") ==
          bad + "field 'image': give either heights (a function or a table of rows) or an image)");
    CHECK(lua.error_of("w:heightfield{ heights = function() return 'up' end }") ==
          bad +
              "field 'heights': the function returned string at x = -0.5, y = -0.5 (a finite "
              "number of metres expected))");
    CHECK(lua.error_of("w:heightfield{ heights = function() return 0 / 0 end }") ==
          bad +
              "field 'heights': the function returned nan at x = -0.5, y = -0.5 (a finite "
              "number of metres expected))");
    CHECK(lua.error_of("w:heightfield{ heights = {{0, 0}, {0}} }") ==
          bad + "field 'heights': row 2 has 1 numbers, row 1 has 2 (rows must be equally long))");
    CHECK(lua.error_of("w:heightfield{ heights = {{0, 0}} }") ==
          bad + "field 'heights': 2 to 4096 rows expected (got 1))");
    CHECK(lua.error_of("w:heightfield{ heights = {{0, 'a'}, {0, 0}} }") ==
          bad + "field 'heights': row 1, entry 2 is not a number)");
    CHECK(lua.error_of("w:heightfield{ samples = { 1, 5 }, heights = function() return 0 end }") ==
          bad + "field 'samples': {nx, ny} with two integers in [2, 4096] expected)");
    CHECK(lua.error_of("w:heightfield{ resolution = 0, heights = function() return 0 end }") ==
          bad + "field 'resolution': positive number of metres expected)");
    CHECK(lua.error_of("w:heightfield{ heights = {{0, 0}, {0, 0}}, max_height = 1 }") ==
          bad + "field 'max_height': only an image takes max_height (heights are in metres))");
    CHECK(lua.error_of("w:heightfield{ length = -1, heights = function() return 0 end }") ==
          bad + "heightfield 4 length must be positive (got -1 m))");
    // an error inside the function is reported where it happened
    CHECK(lua.error_of("w:heightfield{ heights = function() error('no terrain here') end }") ==
          "test:1: no terrain here");
    // a missing image fails at once, naming the path resolved against the script's folder
    CHECK(lua.error_of("w:heightfield{ image = '/tmp/gaitlab_no_such_dir/t.png' }") ==
          bad +
              "heightfield 4 cannot read image '/tmp/gaitlab_no_such_dir/t.png': no such "
              "file or directory)");
}

TEST_CASE("a heightfield image path is relative to the script naming it", "[wrap_world]") {
    LuaFixture lua;
    const std::string file = gaitlab::test::lua_dir() + "/worlds/missing_image.lua";
    const auto e = lua.script_error_of("dofile('" + file + "')");
    // (Lua shortens long file names in positions)
    CHECK_THAT(e.what(), Catch::Matchers::EndsWith(
                             "/missing_image.lua:3: bad argument #1 to 'heightfield' (heightfield "
                             "1 cannot read image '" +
                             gaitlab::test::lua_dir() +
                             "/worlds/no_such_terrain.png': no such "
                             "file or directory)"));
    CHECK(e.file() == file);
    CHECK(e.line() == 3);
}

TEST_CASE("world:add takes a pitch and a roll", "[wrap_world]") {
    LuaFixture lua;
    lua.run(R"(
        r = gaitlab.robot.chain{ modules = 2 }
        w = gaitlab.world{ floor = false, gravity = { 0, 0, 0 } }
        w:add(r, { z = 1, pitch = 30 })
        sim = gaitlab.simulation{ world = w }
        head = r:bodies()[3].position
    )");
    // the head end, 0.144 m along the chain, rises by 0.144 sin 30 deg; the head body's centre
    // is 0.126 along the chain and 0.026 above its bottom
    CHECK(lua.number("head.x") ==
          Approx(0.126 * std::cos(M_PI / 6) - 0.026 * std::sin(M_PI / 6)).margin(1e-6));
    CHECK(lua.number("head.z") ==
          Approx(1 + 0.126 * std::sin(M_PI / 6) + 0.026 * std::cos(M_PI / 6)).margin(1e-6));
    lua.run("r2 = gaitlab.robot.chain{ modules = 1 } w:add(r2, { roll = 90, y = 1 })");
    CHECK(lua.error_of("w:add(gaitlab.robot.chain{ modules = 1 }, { pitch = 0/0 })") ==
          "test:1: bad argument #2 to 'add' (field 'pitch': a number of degrees in [-3600, 3600] "
          "expected, got nan)");
    // ten turns at most, for every angle of a pose: from about 1e16 rad a sine keeps none of
    // the digits written
    CHECK(lua.error_of("w:add(gaitlab.robot.chain{ modules = 1 }, { yaw = 1e300 })") ==
          "test:1: bad argument #2 to 'add' (field 'yaw': a number of degrees in [-3600, 3600] "
          "expected, got 1e+300)");
    CHECK(lua.error_of("w:box{ yaw = -3601 }") ==
          "test:1: bad argument #1 to 'box' (box 1 yaw must be in [-3600, 3600] deg (got -3601))");
    CHECK(lua.error_of("w:ramp{ yaw = 4000 }") ==
          "test:1: bad argument #1 to 'ramp' (ramp 1 yaw must be in [-3600, 3600] deg (got 4000))");
    lua.run("w:box{ yaw = 3600 } w:ramp{ yaw = -3600 }");
    // just outside: the message shows the digit that puts it there
    CHECK(lua.error_of("w:wall{ yaw = 3600.000000001 }") ==
          "test:1: bad argument #1 to 'wall' (wall 1 yaw must be in [-3600, 3600] deg (got "
          "3600.0000000010004))");
    CHECK(lua.error_of("w:add(gaitlab.robot.chain{ modules = 1 }, { pich = 3 })") ==
          "test:1: bad argument #2 to 'add' (unknown key 'pich'; did you mean 'pitch'?)");
}

TEST_CASE("world:triangles gives the objects and the robots where they are", "[wrap_world]") {
    LuaFixture lua;
    lua.run(R"(
        w = gaitlab.world()
        w:box{ size = { 1, 1, 1 } }:ramp{}:stairs{ steps = 2 }
        r = gaitlab.robot.chain{ name = "s", modules = 2 }
        w:add(r, { x = 5 })
        t = w:triangles()
    )");
    // a box, a ramp, two steps, then the robot's three bodies
    CHECK(lua.integer("#t") == 7);
    CHECK(lua.string("t[1].object") == "box 1");
    CHECK(lua.string("t[2].kind") == "ramp");
    CHECK(lua.string("t[4].object") == "stairs 1");
    CHECK(lua.string("t[5].object") == "s tail");
    CHECK(lua.string("t[5].kind") == "robot");
    CHECK(lua.integer("#t[1].vertices") == 12 * 9);
    CHECK(lua.integer("#t[2].vertices") == 8 * 9);  // a wedge: 2 quads, 1 quad, 2 triangles
    // before the simulation the robot is where it was placed; afterwards where it is
    CHECK(lua.number("t[5].vertices[1]") >= 5);
    lua.run(R"(
        sim = gaitlab.simulation{ world = w }
        r:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 60, phase = 0 })
        sim:run(1)
        head = w:triangles()[7].vertices
        top = -1
        for i = 3, #head, 3 do top = math.max(top, head[i]) end
    )");
    CHECK(lua.number("top") > 0.06);  // the head lifted off the floor
}

TEST_CASE("a heightfield from a Lua function gives contact at the height it says", "[wrap_world]") {
    LuaFixture lua;
    lua.run(R"(
        -- bumps on a gentle incline along x (so x and y cannot be mixed up unnoticed)
        function f(x, y)
          return 0.05 + 0.02 * x + 0.02 * math.cos(2 * math.pi * x) * math.cos(2 * math.pi * y)
        end
        w = gaitlab.world{ floor = false }
        w:heightfield{ length = 2, width = 2, resolution = 0.01, heights = f }
        -- 2 cm cubes on hill tops (0, 0), (0.5, 0.5) and in valleys (0.5, 0), (0, -0.5)
        spots = { { 0, 0 }, { 0.5, 0.5 }, { 0.5, 0 }, { 0, -0.5 } }
        for _, p in ipairs(spots) do
          w:box{ size = { 0.02, 0.02, 0.02 }, mass = 0.05,
                 position = { p[1], p[2], f(p[1], p[2]) + 0.015 } }
        end
        sim = gaitlab.simulation{ world = w }
        sim:run(0.3)
        -- the cubes lie still (box_heightfield.h): each one's height now, and its speed
        worst, fastest = 0, 0
        for k, o in ipairs(sim:objects()) do
          local x, y = spots[k][1], spots[k][2]
          worst = math.max(worst, math.abs(o.position.z - 0.01 - f(x, y)))
          local v = o.velocity
          fastest = math.max(fastest, math.sqrt(v.x^2 + v.y^2 + v.z^2))
        end
    )");
    // a cube's face lies on the triangles between the samples, which depart from f by 0.1 mm
    // on these bumps; a height of x and y mixed up, or of a wrong sample, is off by centimetres
    CHECK(lua.number("worst") < 0.0002);
    CHECK(lua.number("fastest") < 0.001);
}

TEST_CASE("gravity and heightfield heights are range-checked", "[wrap_world][limits]") {
    LuaFixture lua;
    CHECK(lua.error_of("gaitlab.world{ gravity = { 0, 0, -1e30 } }") ==
          "test:1: bad argument #1 to 'world' (gravity z must be in [-1000, 1000] m/s² (got "
          "-1e+30))");
    CHECK(lua.error_of("gaitlab.world{ gravity = { 0/0, 0, -9.81 } }") ==
          "test:1: bad argument #1 to 'world' (gravity x must be a finite number)");
    lua.run("w = gaitlab.world{ gravity = { 0, 1000, -1000 } }");
    const std::string bad = "test:1: bad argument #1 to 'heightfield' (";
    CHECK(lua.error_of("w:heightfield{ heights = {{0, 0}, {0, 5000}} }") ==
          bad +
              "heightfield 1 height at grid point (2, 2) must be in [-1000, 1000] m (got "
              "5000))");
    CHECK(lua.error_of("w:heightfield{ heights = {{0, 0}, {0, 1/0}} }") ==
          bad + "heightfield 1 height at grid point (2, 2) must be a finite number)");
    CHECK(lua.error_of("w:heightfield{ samples = {2, 2}, heights = function(x) return x * 1e9 "
                       "end }") ==
          bad +
              "heightfield 1 height at grid point (1, 1) must be in [-1000, 1000] m (got "
              "-500000000))");
    CHECK(lua.error_of("w:heightfield{ image = '/tmp', max_height = 1 }") ==
          bad + "heightfield 1 cannot read image '/tmp': is a directory)");
    CHECK(lua.error_of("w:heightfield{ image = '/dev/zero', max_height = 1 }") ==
          bad +
              "heightfield 1 cannot read image '/dev/zero': not a regular file (a FIFO, "
              "device or socket))");
    CHECK(lua.error_of("w:heightfield{ image = 'x.png', max_height = 1e5 }") ==
          bad + "heightfield 1 max_height must be at most 1000 m (got 100000 m))");
    CHECK(lua.error_of("w:box{ position = { 1e30, 0, 0 } }") ==
          "test:1: bad argument #1 to 'box' (box 1 position x must be in [-10000, 10000] m (got "
          "1e+30))");
    CHECK(lua.error_of("w:box{ mass = 1e30 }") ==
          "test:1: bad argument #1 to 'box' (box 1 mass must be at most 1000000 kg (got 1e+30 "
          "kg))");
}

TEST_CASE("a robot placed inside an object runs with a warning", "[wrap_world][overlap]") {
    LuaFixture lua;
    lua.run(R"(
        w = gaitlab.world()
        w:box{ size = { 1, 1, 1 }, position = { 0.1, 0, 0.2 } }
        r = gaitlab.robot.chain{ name = "snake", modules = 2 }
        w:add(r)
        sim = gaitlab.simulation{ world = w }
        clear = gaitlab.world()
        clear:add(gaitlab.robot.chain{ modules = 2 })
        sim2 = gaitlab.simulation{ world = clear }
    )");
    CHECK(lua.integer("#sim.warnings") == 1);
    CHECK_THAT(lua.string("sim.warnings[1]"),
               Catch::Matchers::StartsWith("body 'tail' of robot 'snake' starts ") &&
                   Catch::Matchers::EndsWith(" mm deep inside box 1: the contact solver will "
                                             "throw it out (place the robot clear of it, e.g. "
                                             "higher)"));
    CHECK(lua.integer("#sim2.warnings") == 0);
}
