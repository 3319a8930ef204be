// Specs built from a simulation file (optimize/runner/src/simulation_spec.cpp): the parameters
// set on the file's controllers evaluate as a build function doing the same by hand, for an XML
// and a Lua simulation file, and bad `simulation` and `set` fields are refused.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "gaitlab/error.h"
#include "gaitlab/optimize/runner.h"
#include "temp_dir.h"

using gaitlab::optimize::Evaluator;
using gaitlab::optimize::load_spec;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

const std::string kWalk = GAITLAB_SOURCE_DIR "/examples/walk.xml";

std::string spec_error(const std::string& path) {
    try {
        load_spec(path);
    } catch (const gaitlab::Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST_CASE("simulation spec: an XML file's controllers set as a build function would") {
    TempDir dir("optimize_simulation_xml");
    write_text(dir / "file.lua", R"(return {
  parameters = { amp = {10, 60}, phase = {30, 180} },
  simulation = ")" + kWalk + R"(",
  set = { amp = "my_sine.amplitude", phase = "my_sine.phase" },
  fitness = "speed", duration = 1,
})");
    write_text(dir / "hand.lua", R"(return {
  parameters = { amp = {10, 60}, phase = {30, 180} },
  build = function(p)
    local sim, info = gaitlab.simulation.load(")" +
                                     kWalk + R"(")
    for _, ctl in ipairs(sim:robot("snake"):controllers()) do
      if ctl.name == "my_sine" then ctl.amplitude = p.amp; ctl.phase = p.phase end
    end
    return sim
  end,
  fitness = "speed", duration = 1,
})");
    Evaluator file(load_spec(dir / "file.lua"));
    Evaluator hand(load_spec(dir / "hand.lua"));
    const double a = file.evaluate({20, 120});
    const double b = file.evaluate({50, 60});
    CHECK(a != b);
    CHECK(a == hand.evaluate({20, 120}));
    CHECK(b == hand.evaluate({50, 60}));
    // the best saved as a simulation file carries the values
    file.save({50, 60}, dir / "best/best.xml");
    CHECK(
        gaitlab::test::read_text(dir / "best/best.snake.actuation.xml").find("amplitude=\"50\"") !=
        std::string::npos);
}

TEST_CASE("simulation spec: a Lua file returning a simulation, parameters named by target") {
    TempDir dir("optimize_simulation_lua");
    write_text(dir / "snake.lua",
               R"(local robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
local world = gaitlab.world{}
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ frequency = 1 })
return gaitlab.simulation{ world = world }
)");
    // without set, the parameters' names say what they set; the file is found next to the spec
    write_text(dir / "file.lua", R"(return {
  parameters = { ["sine.amplitude"] = {10, 60} },
  simulation = "snake.lua",
  fitness = "distance", duration = 0.5,
})");
    write_text(dir / "hand.lua", R"(return {
  parameters = { ["sine.amplitude"] = {10, 60} },
  build = function(p)
    local robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
    local world = gaitlab.world{}
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{ frequency = 1,
                                                         amplitude = p["sine.amplitude"] })
    return gaitlab.simulation{ world = world }
  end,
  fitness = "distance", duration = 0.5,
})");
    Evaluator file(load_spec(dir / "file.lua"));
    Evaluator hand(load_spec(dir / "hand.lua"));
    CHECK(file.evaluate({25}) == hand.evaluate({25}));
    CHECK(file.evaluate({55}) == hand.evaluate({55}));
    CHECK(file.evaluate({25}) != file.evaluate({55}));
}

TEST_CASE("simulation spec: bad simulation and set fields are refused naming what is wrong") {
    TempDir dir("optimize_simulation_bad");
    write_text(dir / "nosim.lua", "return 42\n");
    struct Case {
        std::string fields, message;
    };
    const std::string walk = "simulation = '" + kWalk + "', ";
    const std::vector<Case> cases = {
        {walk + "set = { a = 'my_sine.amplitude' }, build = function() end",
         "build: give build or simulation, not both"},
        {"simulation = 'none.xml', set = { a = 'sine.amplitude' }",
         "simulation: " + dir.str() + "/none.xml: no such file (relative to the spec's folder)"},
        {"simulation = 3",
         "simulation: a simulation file's name (FILE.xml or FILE.lua) "
         "expected, got number"},
        {"build = function() end, set = { a = 'sine.amplitude' }",
         "set: only with simulation = \"FILE.xml\" (a build function sets what it likes)"},
        {walk + "set = 'my_sine'",
         "set: a table { PARAMETER = \"CONTROLLER.PARAMETER\", ... } expected, got string"},
        {walk + "set = { a = 3 }",
         "set: a table { PARAMETER = \"CONTROLLER.PARAMETER\", ... } expected (names and "
         "strings)"},
        {walk + "set = { a = 'sine.amplitude' }",
         "set.a: " + kWalk + " has no controller 'sine' (it has 'my_sine', 'offset')"},
        {walk + "set = { a = 'my_sine.amplitud' }",
         "set.a: controller 'my_sine' has no parameter 'amplitud' (it has 'amplitude', "
         "'frequency', 'phase')"},
        {walk + "set = { a = 'amplitude' }",
         "set.a: 'CONTROLLER.PARAMETER' expected (a controller of " + kWalk +
             " and one of its parameters, e.g. 'sine.amplitude'), got 'amplitude'"},
        {walk + "set = { a = 'my_sine.amplitude', b = 'my_sine.phase' }",
         "set.b: no parameter 'b' to set (set names parameters)"},
        {walk, "parameters.a: 'CONTROLLER.PARAMETER' expected (a controller of " + kWalk +
                   " and one of its parameters, e.g. 'sine.amplitude'), got 'a'"},
        {"simulation = 'nosim.lua'", "simulation: " + dir.str() +
                                         "/nosim.lua must return a simulation (return "
                                         "gaitlab.simulation{ ... }), got number"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        const std::string file = dir / ("bad" + std::to_string(i) + ".lua");
        write_text(file, "return { parameters = { a = {0, 1} }, fitness = 'speed', duration = 1, " +
                             cases[i].fields + " }");
        INFO(cases[i].fields);
        CHECK(spec_error(file) == file + ": " + cases[i].message);
    }
    // a range wider than the controller's
    write_text(dir / "wide.lua", "return { parameters = { a = {10, 600} }, " + walk +
                                     "set = { a = 'my_sine.amplitude' }, fitness = 'speed', "
                                     "duration = 1 }");
    CHECK(spec_error(dir / "wide.lua")
              .rfind(dir / "wide.lua" +
                         ": parameters.a: the range [10, 600] goes outside my_sine.amplitude's [0",
                     0) == 0);
}
