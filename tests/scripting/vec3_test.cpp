// gaitlab.Vec3, the vectors the engine returns (stdlib/vec3.lua).
#include <catch2/catch.hpp>

#include "lua_fixture.h"

using gaitlab::test::LuaFixture;

TEST_CASE("Vec3 arithmetic, norm and tostring", "[vec3]") {
    LuaFixture lua;
    lua.run("a = gaitlab.vec3(1, 2, 3) b = gaitlab.vec3(4, -5, 6)");
    CHECK(lua.string("tostring(a + b)") == "(5, -3, 9)");
    CHECK(lua.string("tostring(a - b)") == "(-3, 7, -3)");
    CHECK(lua.string("tostring(-a)") == "(-1, -2, -3)");
    CHECK(lua.string("tostring(2 * a)") == "(2, 4, 6)");
    CHECK(lua.string("tostring(a * 2)") == "(2, 4, 6)");
    CHECK(lua.string("tostring(b / 2)") == "(2, -2.5, 3)");
    CHECK(lua.string("tostring(gaitlab.vec3(1 / 3, 1e-7, 123456789))") ==
          "(0.333333, 1e-07, 1.23457e+08)");
    CHECK(lua.number("a:dot(b)") == 12);
    CHECK(lua.string("tostring(a:cross(b))") == "(27, 6, -13)");
    CHECK(lua.number("gaitlab.vec3(3, 4, 0):norm()") == 5);
    CHECK(lua.string("table.concat({ a:unpack() }, ',')") == "1,2,3");
    CHECK(lua.boolean("a == gaitlab.vec3(1, 2, 3)"));
    CHECK_FALSE(lua.boolean("a == b"));
    CHECK(lua.string("tostring(gaitlab.vec3())") == "(0, 0, 0)");
    CHECK(lua.string("getmetatable(a + b).__name") == "gaitlab.Vec3");
}

TEST_CASE("the engine returns Vec3 values", "[vec3]") {
    LuaFixture lua;
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 2 }
        world = gaitlab.world()
        world:add(robot)
        sim = gaitlab.simulation{ world = world }
        p = robot:position()
    )");
    CHECK(lua.string("getmetatable(p).__name") == "gaitlab.Vec3");
    CHECK(lua.number("(p - p):norm()") == 0);
    CHECK(lua.number("(robot:velocity() * 0):norm()") == 0);
    CHECK_THAT(lua.string("tostring(p)"), Catch::Matches(R"(\(0\.072, -?[0-9.e+-]+, 0\.026\))"));
}
