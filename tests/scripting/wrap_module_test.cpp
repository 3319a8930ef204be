// gaitlab.module and gaitlab.modules: the module library and custom module types
// (scripting/src/wrap_module.cpp), and chains built from them.
#include <catch2/catch.hpp>

#include "lua_fixture.h"

using gaitlab::test::LuaFixture;

TEST_CASE("the module library holds y1 and cube", "[wrap_module]") {
    LuaFixture lua;
    CHECK(lua.string("tostring(gaitlab.modules.y1)") == "gaitlab.Module 'y1'");
    CHECK(lua.string("gaitlab.modules.y1.shape") == "box");
    CHECK(lua.number("gaitlab.modules.y1.length") == 0.072);
    CHECK(lua.number("gaitlab.modules.y1.mass") == 0.05);
    CHECK(lua.number("gaitlab.modules.y1.range[2]") == Approx(90));
    CHECK(lua.number("gaitlab.modules.y1.max_speed") == Approx(4.5 * 180 / M_PI));
    CHECK(lua.number("gaitlab.modules.y1.max_torque") == 0.4);
    CHECK(lua.string("gaitlab.modules.y1.axis") == "bend");
    CHECK(lua.number("gaitlab.modules.cube.width") == 0.06);
    CHECK(lua.number("gaitlab.modules.cube.max_torque") == 1.0);
    CHECK(lua.boolean("gaitlab.modules.cube.colour == nil"));
}

TEST_CASE("chains are built from a module named or given", "[wrap_module]") {
    LuaFixture lua;
    lua.run(R"(
        a = gaitlab.robot.chain{ modules = 3, module = "cube" }
        b = gaitlab.robot.chain{ modules = 3, module = gaitlab.modules.cube }
        y = gaitlab.robot.chain{ modules = 3 }
    )");
    CHECK(lua.number("a:bodies()[2].size.x") == Approx(0.06));
    CHECK(lua.number("b:bodies()[2].mass") == Approx(0.1));
    CHECK(lua.number("y:bodies()[2].size.x") == Approx(0.072));
    const std::string bad = "test:1: bad argument #1 to 'chain' (field 'module': ";
    CHECK(lua.error_of("gaitlab.robot.chain{ modules = 2, module = 'cub' }") ==
          bad + "unknown module type 'cub'; did you mean 'cube'? (module types: cube, y1))");
    CHECK(lua.error_of("gaitlab.robot.chain{ modules = 2, module = 3 }") ==
          bad + "module type name or gaitlab.Module expected, got number)");
    CHECK(lua.error_of("gaitlab.robot.chain{ modules = 2, modul = 'cube' }") ==
          "test:1: bad argument #1 to 'chain' (unknown key 'modul'; did you mean 'module'?)");
}

TEST_CASE("gaitlab.module defines a custom module type", "[wrap_module]") {
    LuaFixture lua;
    lua.run(R"(
        big = gaitlab.module{ name = "big", shape = "cylinder", length = 0.1, radius = 0.03,
                              mass = 0.08, range = { -60, 60 }, max_speed = 180,
                              max_torque = 1.0 }
        r = gaitlab.robot.chain{ name = "tube", modules = 4, connection = "pitch-yaw",
                                 module = "big" }
        j = r:joints()[2]
        seg = r:bodies()[2]
    )");
    CHECK(lua.boolean("gaitlab.modules.big == big"));
    CHECK(lua.string("big.shape") == "cylinder");
    CHECK(lua.number("big.max_speed") == Approx(180));
    CHECK(lua.number("j.min") == Approx(-60));
    CHECK(lua.number("j.max") == Approx(60));
    CHECK(lua.string("j.role") == "yaw");
    CHECK(lua.number("seg.mass") == Approx(0.08));
    CHECK(lua.number("seg.size.x") == Approx(0.1));
    CHECK(lua.number("seg.size.y") == Approx(0.06));
    CHECK(lua.string("seg.shape") == "cylinder");
    CHECK(lua.string("gaitlab.robot.chain{ modules = 1 }:bodies()[1].shape") == "box");
    CHECK(lua.number("#r") == 4);
    // it runs: a chain of cylinders lies at its radius
    lua.run(R"(
        w = gaitlab.world() w:add(r)
        sim = gaitlab.simulation{ world = w } sim:run(0.5)
    )");
    CHECK(lua.number("r:position().z") == Approx(0.03).margin(0.001));
    // defining it again replaces it
    lua.run("gaitlab.module{ name = 'big', mass = 0.2 }");
    CHECK(lua.number("gaitlab.modules.big.mass") == 0.2);
    CHECK(lua.string("gaitlab.modules.big.shape") == "box");  // from y1, the default base
}

TEST_CASE("a custom module can start from another one", "[wrap_module]") {
    LuaFixture lua;
    lua.run(R"(
        strong = gaitlab.module{ name = "strong", base = "cube", max_torque = 2 }
        stronger = gaitlab.module{ name = "stronger", base = strong, max_torque = 3 }
    )");
    CHECK(lua.number("strong.length") == 0.06);
    CHECK(lua.number("strong.max_torque") == 2);
    CHECK(lua.number("stronger.mass") == 0.1);
    CHECK(lua.number("stronger.max_torque") == 3);
}

TEST_CASE("twist modules make roll joints", "[wrap_module]") {
    LuaFixture lua;
    lua.run(R"(
        gaitlab.module{ name = "roller", axis = "twist" }
        r = gaitlab.robot.chain{ modules = 3, module = "roller" }
        g = r:group("roll")
    )");
    CHECK(lua.integer("#g") == 3);
    CHECK(lua.string("r:joints()[1].role") == "roll");
    CHECK(lua.string("gaitlab.modules.roller.axis") == "twist");
}

TEST_CASE("gaitlab.module rejects bad definitions", "[wrap_module]") {
    LuaFixture lua;
    const std::string bad = "test:1: bad argument #1 to 'module' (";
    CHECK(lua.error_of("gaitlab.module{ mass = 1 }") ==
          bad + "field 'name': string expected, got nil)");
    CHECK(lua.error_of("gaitlab.module{ name = 'y1' }") ==
          bad + "field 'name': 'y1' is a built-in module type (choose another name))");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', shape = 'sphere' }") ==
          bad + "field 'shape': 'box' or 'cylinder' expected, got 'sphere')");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', axis = 'roll' }") ==
          bad + "field 'axis': 'bend' or 'twist' expected, got 'roll')");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', mass = -0.1 }") ==
          bad + "module 'm' mass must be positive (got -0.1 kg))");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', friction = 2 }") ==
          bad + "module 'm' friction must be in [0, 1] (got 2))");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', shape = 'cylinder', radius = -1 }") ==
          bad + "module 'm' radius must be positive (got -1 m))");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', range = { 60, -60 } }") ==
          bad + "module 'm' joint range must satisfy -180 <= min < max <= 180 deg)");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', range = 60 }") ==
          bad + "field 'range': {min, max} in degrees expected)");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', max_speed = -3 }") ==
          bad + "field 'max_speed': must be in (0, 57295.77951308232] deg/s (got -3 deg/s))");
    // the engine's bound (1000 rad/s) in the unit the script gave
    CHECK(lua.error_of("gaitlab.module{ name = 'm', max_speed = 1e308 }") ==
          bad + "field 'max_speed': must be in (0, 57295.77951308232] deg/s (got 1e+308 deg/s))");
    // a range is two numbers and nothing else, as a vector is three
    CHECK(lua.error_of("gaitlab.module{ name = 'm', range = { -60, 60, 90 } }") ==
          bad + "field 'range': 2 numbers expected ({min, max}), got 3)");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', range = { -60, 60, step = 5 } }") ==
          bad + "field 'range': unknown key 'step' (a range's keys are min and max))");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', range = { -60, 'x' } }") ==
          bad + "field 'range': range expected ({min, max} with two numbers))");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', max_torqe = 1 }") ==
          bad + "unknown key 'max_torqe'; did you mean 'max_torque'?)");
    CHECK(lua.error_of("gaitlab.module{ name = 'm', base = 'nope' }") ==
          bad + "field 'base': unknown module type 'nope' (module types: cube, y1))");
    // nothing was added by the failed definitions
    CHECK(lua.boolean("gaitlab.modules.m == nil"));
}

TEST_CASE("a pitch-yaw chain of flat box modules is rejected", "[wrap_module]") {
    LuaFixture lua;
    lua.run("gaitlab.module{ name = 'flat', height = 0.03 }");
    CHECK(lua.error_of("gaitlab.robot.chain{ modules = 2, connection = 'pitch-yaw', "
                       "module = 'flat' }") ==
          "test:1: bad argument #1 to 'chain' (a pitch-yaw chain needs modules with a square "
          "cross-section (module 'flat' is 0.052 x 0.03 m; make width = height or use a "
          "cylinder))");
}

TEST_CASE("gaitlab.modules is read-only and lists the types gaitlab.module defines",
          "[wrap_module]") {
    LuaFixture lua;
    const std::string read_only = "test:1: gaitlab.modules is read-only";
    const std::string how = ": define a module type with gaitlab.module{ name = ..., ... }";
    // the built-in types cannot be removed or replaced, nor other values added
    CHECK(lua.error_of("gaitlab.modules.cube = nil") == read_only + " (cannot set 'cube')" + how);
    CHECK(lua.error_of("gaitlab.modules.y1 = nil") == read_only + " (cannot set 'y1')" + how);
    CHECK(lua.error_of("gaitlab.modules.y1 = gaitlab.modules.cube") ==
          read_only + " (cannot set 'y1')" + how);
    CHECK(lua.error_of("gaitlab.modules.newthing = 5") ==
          read_only + " (cannot set 'newthing')" + how);
    CHECK(lua.error_of("gaitlab.modules[1] = 5") == read_only + how);
    CHECK(lua.error_of("setmetatable(gaitlab.modules, nil)") ==
          "test:1: cannot change a protected metatable");
    CHECK(lua.string("getmetatable(gaitlab.modules)") == "gaitlab.modules");
    CHECK(lua.string("tostring(gaitlab.modules.y1)") == "gaitlab.Module 'y1'");
    CHECK(lua.number("gaitlab.robot.chain{ modules = 2, module = 'cube' }:bodies()[2].mass") ==
          Approx(0.1));
    CHECK(lua.boolean("gaitlab.modules.newthing == nil"));
    // gaitlab.module still adds types, which pairs lists in name order; # and ipairs see no
    // list, as before
    lua.run(R"(
        gaitlab.module{ name = "tube", shape = "cylinder" }
        gaitlab.module{ name = "big", mass = 0.2 }
        names = {}
        for name, m in pairs(gaitlab.modules) do names[#names + 1] = name .. "=" .. m.name end
        listed = 0
        for _ in ipairs(gaitlab.modules) do listed = listed + 1 end
    )");
    CHECK(lua.string("table.concat(names, ' ')") == "big=big cube=cube tube=tube y1=y1");
    CHECK(lua.integer("listed") == 0);
    CHECK(lua.integer("#gaitlab.modules") == 0);
    CHECK(lua.number("gaitlab.modules.big.mass") == 0.2);
    CHECK(lua.error_of("gaitlab.modules.tube = nil") == read_only + " (cannot set 'tube')" + how);
    CHECK(lua.string("gaitlab.modules.tube.shape") == "cylinder");
}
