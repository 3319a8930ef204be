// gaitlab.world: floor, gravity, boxes and placing robots (scripting/src/wrap_world.cpp).
#include <catch2/catch.hpp>

#include "lua_fixture.h"

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
    CHECK(lua.error_of("w:box{ sise = { 1, 1, 1 } }") ==
          bad + "unknown key 'sise'; did you mean 'size'?)");
    CHECK(lua.error_of("w:box()") == bad + "table expected, got no value)");
    // a valid box returns the world, so calls chain
    CHECK(lua.string("tostring(w:box{ size = { 1, 1, 0.1 } }:box{ mass = 1 })") ==
          "gaitlab.World (0 robots, 2 boxes)");
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
