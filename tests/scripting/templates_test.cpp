// The controller templates embedded from stdlib/templates (the wizard starts new controllers
// from them): each runs as it is, the gait templates move a snake, and write_template copies one
// into a file that loads and runs the same.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "lua_fixture.h"

using gaitlab::test::LuaFixture;
namespace fs = std::filesystem;

namespace {

// drives the pitch joints of an 8-module snake with `ctl` (a Lua expression) for 10 s and
// returns how far it moved, m
double distance(LuaFixture& lua, const std::string& ctl) {
    lua.run(R"(
        robot = gaitlab.robot.chain{ modules = 8 }
        world = gaitlab.world{ floor = { friction = 0.8 } }
        world:add(robot)
        ctl = robot:group("pitch"):drive()" +
            ctl + R"()
        sim = gaitlab.simulation{ world = world }
        sim:run(10)
        d = robot:displacement()
    )");
    return lua.number("d:norm()");
}

}  // namespace

TEST_CASE("the templates are listed and each runs as it is", "[templates]") {
    LuaFixture lua;
    lua.run("names = gaitlab.controller.templates()");
    CHECK(lua.string("table.concat(names, ' ')") == "blank cpg_chain sine");
    // the gait templates move the snake like the built-in sine; blank holds it still
    const double sine = distance(lua, "gaitlab.controller.template('sine')()");
    CHECK(lua.string("ctl.name") == "my_sine");
    CHECK(sine > 0.2);
    const double cpg = distance(lua, "gaitlab.controller.template('cpg_chain')()");
    CHECK(lua.string("ctl.name") == "my_cpg");
    CHECK(cpg > 0.2);
    CHECK(lua.number("ctl:values().radius[1]") == Approx(40).margin(0.01));
    const double blank = distance(lua, "gaitlab.controller.template('blank'){ angle = 0 }");
    CHECK(blank < 0.001);
    // the sine template is the built-in sine, to the bit
    const double builtin = distance(lua, "gaitlab.controllers.sine{}");
    CHECK(sine == builtin);
    CHECK(lua.error_of("gaitlab.controller.template('sin')") ==
          "test:1: bad argument #1 to 'template' (unknown template 'sin'; did you mean 'sine'? "
          "(templates: blank, cpg_chain, sine))");
}

TEST_CASE("the cpg_chain template locks its neighbours to the commanded lag", "[templates]") {
    LuaFixture lua;
    distance(lua, "gaitlab.controller.template('cpg_chain'){ phase = 90 }");
    for (int m = 1; m < 4; ++m) {
        const std::string a = "ctl:values().theta[" + std::to_string(m) + "]";
        const std::string b = "ctl:values().theta[" + std::to_string(m + 1) + "]";
        double lag = (lua.number(b) - lua.number(a)) * 180 / 3.14159265358979323846;
        lag = std::fmod(lag + 720, 360);
        CHECK(lag == Approx(90).margin(1));
    }
}

TEST_CASE("write_template copies a template to a file that loads and runs the same",
          "[templates]") {
    const fs::path dir =
        fs::temp_directory_path() /
        ("gaitlab_templates_" +
         std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    fs::create_directories(dir);
    const std::string file = (dir / "walk.lua").string();
    LuaFixture lua;
    lua.run("FILE = '" + file + "'");
    lua.run("written = assert(gaitlab.controller.write_template('sine', FILE))");
    CHECK(lua.string("written") == file);
    const double from_file = distance(lua, "gaitlab.controller.load(FILE){ amplitude = 30 }");
    const double embedded = distance(lua, "gaitlab.controller.template('sine'){ amplitude = 30 }");
    CHECK(from_file == embedded);
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    CHECK(text.str().rfind("-- A sine-wave gait", 0) == 0);
    // never overwrites
    lua.run("ok, err = gaitlab.controller.write_template('blank', FILE)");
    CHECK(lua.boolean("ok == nil"));
    CHECK(lua.string("err") == file + ": file exists (templates never overwrite)");
    lua.run("ok, err = gaitlab.controller.write_template('blank', FILE .. '/no/such/dir.lua')");
    CHECK(lua.string("err").rfind("cannot write " + file + "/no/such/dir.lua: ", 0) == 0);
    // a folder or a device there is no template that exists (both said "file exists")
    lua.run("ok, err = gaitlab.controller.write_template('blank', '" + dir.string() + "')");
    CHECK(lua.string("err") == dir.string() + ": is a directory");
    lua.run("ok, err = gaitlab.controller.write_template('blank', '/dev/null')");
    CHECK(lua.string("err") == "/dev/null: not a regular file (a FIFO, device or socket)");
    fs::remove_all(dir);
}
