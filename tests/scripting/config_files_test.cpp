// Configuration files from Lua (scripting/src/config_files.cpp and the save/load bindings): a
// simulation saved with sim:save and loaded with gaitlab.simulation.load runs the same
// trajectory to the bit; robots, worlds and actuations save and load on their own; bad files
// give nil and "FILE:LINE: ..." messages; controllers defined inside a script cannot be saved.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "gaitlab/xml.h"
#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;

namespace {

// a two-robot scene with a box, a Lua controller file, a template and built-ins, parameters
// changed online; defines build() -> sim, robots
const char* kScene = R"(
    function build()
      local MySine = gaitlab.controller.load(EXAMPLES .. "/controllers/my_sine.lua")
      local snake = gaitlab.robot.chain{ name = "snake", modules = 6, connection = "pitch-yaw" }
      local worm = gaitlab.robot.chain{ name = "worm", modules = 4 }
      local world = gaitlab.world{ floor = { friction = 0.7 } }
      world:box{ size = {0.1, 0.2, 0.05}, position = {0.6, 0.3, 0.025}, yaw = 30 }
      world:add(snake, { x = 0.1, yaw = 15 })
      world:add(worm, { y = 1 })
      snake:group("pitch"):drive(MySine{ amplitude = 30 })
      local s = snake:group{ 2, 4 }:drive(gaitlab.controllers.sine{ amplitude = 20, phase = 90 })
      s.frequency = 0.7
      worm:group("all"):drive(gaitlab.controller.template("cpg_chain"){ phase = 100 })
      snake:sensor{ kind = "imu", module = 2 }
      snake:sensor{ kind = "range", name = "eye", module = 6, max_range = 1.5 }:off()
      local sim = gaitlab.simulation{ world = world, control_every = 10, seed = 3 }
      return sim, { snake = snake, worm = worm }
    end
)";

// a 3-module snake driven by a sine, its world and simulation, and both(...), which keeps every
// result of a call (a save's path, or nil and its message)
const char* kSavedSnake = R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
        robot:group("pitch"):drive(gaitlab.controllers.sine{})
        world = gaitlab.world()
        world:add(robot)
        sim = gaitlab.simulation{ world = world }
        local function both(...) return { ... } end
)";

// the value of the first attribute `name` in the file at `path` ("" if there is none)
std::string attribute(const std::string& path, const std::string& name) {
    const std::string text = gaitlab::test::read_text(path);
    const size_t at = text.find(" " + name + "=\"");
    if (at == std::string::npos) return "";
    const size_t start = at + name.size() + 3;
    return text.substr(start, text.find('"', start) - start);
}

}  // namespace

TEST_CASE("a saved simulation loads and runs the same trajectory to the bit", "[config_files]") {
    TempDir dir("sim_save");
    LuaFixture lua;
    lua.run("EXAMPLES = '" GAITLAB_SOURCE_DIR "/examples'  DIR = '" + dir.path.string() + "'");
    lua.run(kScene);
    lua.run(R"(
        sim, robots = build()
        saved = assert(sim:save(DIR .. "/walk.xml", { duration = 2 }))
        sim:run(2)
        loaded, setup = assert(gaitlab.simulation.load(DIR .. "/walk.xml"))
        loaded:run(setup.duration)
    )");
    CHECK(lua.string("saved") == dir.file("walk.xml"));
    for (const char* f :
         {"walk.xml", "walk.environment.xml", "walk.snake.robot.xml", "walk.snake.actuation.xml",
          "walk.worm.robot.xml", "walk.worm.actuation.xml"}) {
        CHECK(std::filesystem::exists(dir.file(f)));
    }
    CHECK(lua.number("setup.duration") == 2);
    CHECK(lua.string("setup.name") == "walk");
    // the line of <simulation>, after the XML declaration and <gaitlab>
    CHECK(lua.integer("setup.line") == 3);
    CHECK(lua.integer("loaded.control_every") == 10);
    CHECK(lua.integer("loaded.seed") == 3);
    CHECK(lua.number("robots.snake:displacement():norm()") > 0.01);
    for (const char* name : {"snake", "worm"}) {
        for (const char* axis : {"x", "y", "z"}) {
            const std::string a = std::string("robots.") + name + ":position()." + axis;
            const std::string b = std::string("setup.robots.") + name + ":position()." + axis;
            CHECK(lua.number(a) == lua.number(b));
        }
    }
    // the table's robots and controllers are the simulation's: the same handles
    CHECK(lua.boolean("rawequal(setup.robots.snake, loaded:robot('snake'))"));
    CHECK(lua.boolean("setup.controllers.snake[2] == loaded:robot('snake'):controllers()[2]"));
    CHECK(lua.boolean("setup.robots.snake ~= robots.snake"));
    // sensors are part of the robot file, switched on or off as they were
    CHECK(lua.integer("#setup.robots.snake:sensors()") == 2);
    CHECK(lua.boolean("setup.robots.snake:sensor('imu2').enabled"));
    CHECK(lua.boolean("setup.robots.snake:sensor('eye').enabled") == false);
    CHECK(lua.number("setup.robots.snake:sensor('eye').max_range") == 1.5);
    CHECK(lua.number("setup.robots.snake:sensor('imu2'):read().roll") ==
          lua.number("robots.snake:sensor('imu2'):read().roll"));
    // the online change is saved: the loaded sine runs at 0.7 Hz
    CHECK(lua.number("setup.controllers.snake[2].frequency") == 0.7);
    CHECK(lua.string("setup.controllers.worm[1].name") == "my_cpg");
    // the actuation file names the controller file relative to itself or absolutely, as their
    // folders allow: either way it leads to the file
    const std::string act = dir.file("walk.snake.actuation.xml");
    CHECK(gaitlab::resolve_path(act, attribute(act, "file")) == GAITLAB_SOURCE_DIR
          "/examples/controllers/my_sine.lua");
}

TEST_CASE("robots, worlds and actuations save and load on their own", "[config_files]") {
    TempDir dir("parts");
    LuaFixture lua;
    lua.run("EXAMPLES = '" GAITLAB_SOURCE_DIR "/examples'  DIR = '" + dir.path.string() + "'");
    lua.run(kScene);
    lua.run(R"(
        sim, robots = build()
        assert(robots.snake:save(DIR .. "/snake.xml"))
        assert(robots.snake:actuation():save(DIR .. "/snake_act.xml"))
        assert(robots.worm:actuation():save(DIR .. "/worm_act.xml"))
        sim:run(1)

        local snake = assert(gaitlab.robot.load(DIR .. "/snake.xml"))
        local worm = gaitlab.robot.chain{ name = "worm", modules = 4 }
        local world = gaitlab.world{ floor = { friction = 0.7 } }
        world:box{ size = {0.1, 0.2, 0.05}, position = {0.6, 0.3, 0.025}, yaw = 30 }
        world:add(snake, { x = 0.1, yaw = 15 })
        world:add(worm, { y = 1 })
        assert(world:save(DIR .. "/world.xml"))
        act = assert(gaitlab.actuation.load(DIR .. "/snake_act.xml"))
        ctls = snake:actuate(act)
        worm:actuate(assert(gaitlab.actuation.load(DIR .. "/worm_act.xml")))
        sim2 = gaitlab.simulation{ world = world, control_every = 10, seed = 3 }
        sim2:run(1)
        copy = { snake = snake, worm = worm }

        -- a loaded world places robots by name when they are added without a pose
        world3 = assert(gaitlab.world.load(DIR .. "/world.xml"))
        snake3 = assert(gaitlab.robot.load(DIR .. "/snake.xml"))
        world3:add(snake3)
        sim3 = gaitlab.simulation{ world = world3 }
    )");
    CHECK(lua.integer("#act") == 2);
    CHECK(lua.string("act:groups()[1].joints") == "pitch");
    CHECK(lua.integer("act:groups()[2].joints[2]") == 4);
    CHECK(lua.string("act:groups()[2].controller.builtin") == "sine");
    CHECK(lua.number("act:groups()[2].controller.params.frequency") == 0.7);
    CHECK(lua.string("tostring(act)") == "gaitlab.Actuation (2 groups)");
    CHECK(lua.integer("#ctls") == 2);
    CHECK(lua.boolean("ctls[1].name == 'my_sine'"));
    for (const char* name : {"snake", "worm"}) {
        for (const char* axis : {"x", "y", "z"}) {
            const std::string a = std::string("robots.") + name + ":position()." + axis;
            const std::string b = std::string("copy.") + name + ":position()." + axis;
            CHECK(lua.number(a) == lua.number(b));
        }
    }
    const double tail_x = lua.number("snake3:bodies()[1].position.x");
    const double tail_y = lua.number("snake3:bodies()[1].position.y");
    CHECK(tail_x == Approx(0.1 + 0.018 * std::cos(15 * 3.14159265358979 / 180)));
    CHECK(tail_y == Approx(0.018 * std::sin(15 * 3.14159265358979 / 180)));
}

TEST_CASE("every object of the world library saves and loads exactly", "[config_files]") {
    TempDir dir("world_library");
    LuaFixture lua;
    lua.run("EXAMPLES = '" GAITLAB_SOURCE_DIR "/examples'  DIR = '" + dir.path.string() + "'");
    lua.run(R"(
        world = gaitlab.world{ floor = { friction = 0.6 }, gravity = {0, 0.5, -9.81} }
        world:box{ size = {0.1, 0.2, 0.05}, position = {0.6, 0.3, 0.025}, yaw = 30, mass = 0.2 }
        world:wall{ length = 1.2, height = 0.15, position = {0, 0.8, 0}, yaw = 5 }
        world:ramp{ slope = 12.5, length = 0.6, width = 0.4, position = {1, -1, 0} }
        world:stairs{ steps = 4, step_height = 0.015, step_depth = 0.12, landing = 0.2,
                      position = {-1, 1, 0}, yaw = 90, friction = 0.7 }
        world:cylinder{ radius = 0.04, length = 0.3, lying = true, position = {0.3, -0.5, 0.04},
                        mass = 0.3 }
        world:pipe{ radius = 0.07, length = 0.8, sides = 12, position = {2, 0, 0.08} }
        world:rubble{ count = 20, seed = 7, position = {-2, -2, 0}, max_height = 0.025 }
        world:heightfield{ length = 0.6, width = 0.4, samples = {7, 5},
                           heights = function(x, y) return 0.01 * x + 0.02 * y * y end,
                           position = {0, -2, 0} }
        world:heightfield{ image = EXAMPLES .. "/terrain.png", max_height = 0.04, length = 1.5,
                           width = 1, position = {3, 3, 0}, yaw = 45 }
        assert(world:save(DIR .. "/library.xml"))
        copy = assert(gaitlab.world.load(DIR .. "/library.xml"))
        a, b = world:triangles(), copy:triangles()
    )");
    CHECK(lua.string("tostring(copy)") == lua.string("tostring(world)"));
    REQUIRE(lua.integer("#a") == lua.integer("#b"));
    const long long n = lua.integer("#a");
    CHECK(n >= 9);
    lua.run(R"(
        same = true
        for i = 1, #a do
          if a[i].kind ~= b[i].kind or #a[i].vertices ~= #b[i].vertices then same = false end
          for k = 1, #a[i].vertices do
            if a[i].vertices[k] ~= b[i].vertices[k] then same = false end
          end
        end
    )");
    CHECK(lua.boolean("same"));
    const std::string text = gaitlab::test::read_text(dir.file("library.xml"));
    CHECK(text.find("<ramp slope=\"12.5\"") != std::string::npos);
    CHECK(gaitlab::resolve_path(dir.file("library.xml"),
                                attribute(dir.file("library.xml"), "image")) == GAITLAB_SOURCE_DIR
          "/examples/terrain.png");
}

TEST_CASE("bad files give nil and a message naming file and line", "[config_files]") {
    TempDir dir("bad_files");
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    gaitlab::test::write_text(dir.file("robot.xml"),
                              "<gaitlab version=\"1\">\n<robot>\n<chain modules=\"3\" "
                              "conection=\"pitch-yaw\"/>\n</robot>\n</gaitlab>\n");
    lua.run("r, err = gaitlab.robot.load(DIR .. '/robot.xml')");
    CHECK(lua.boolean("r == nil"));
    CHECK(lua.string("err") == dir.file("robot.xml") +
                                   ":3: robot/chain[1]: unknown attribute 'conection'; did you "
                                   "mean 'connection'? (expected 'modules', 'connection', "
                                   "'module')");
    lua.run("r, err = gaitlab.world.load(DIR .. '/none.xml')");
    CHECK(lua.string("err") ==
          dir.file("none.xml") + ": cannot read the file: No such file or directory");

    // parameters are checked against the controller when the actuation is applied; the
    // message names the script line and the file line
    gaitlab::test::write_text(dir.file("act.xml"),
                              "<gaitlab version=\"1\">\n<actuation>\n<group joints=\"pitch\">\n"
                              "<controller builtin=\"sine\" amplitud=\"30\"/>\n</group>\n"
                              "<group joints=\"1 9\">\n<controller builtin=\"offset\"/>\n"
                              "</group>\n</actuation>\n</gaitlab>\n");
    lua.run("act = assert(gaitlab.actuation.load(DIR .. '/act.xml'))");
    lua.run("robot = gaitlab.robot.chain{ modules = 4 }");
    CHECK(lua.error_of("robot:actuate(act)") ==
          "test:1: " + dir.file("act.xml") +
              ":4: controller 'sine' has no parameter 'amplitud'; did you mean 'amplitude'? "
              "(parameters: amplitude, frequency, phase, phase0, offset)");
    gaitlab::test::write_text(dir.file("act2.xml"),
                              "<gaitlab version=\"1\">\n<actuation>\n"
                              "<group joints=\"1 9\">\n<controller builtin=\"offset\"/>\n"
                              "</group>\n</actuation>\n</gaitlab>\n");
    CHECK(lua.error_of("robot:actuate(assert(gaitlab.actuation.load(DIR .. '/act2.xml')))") ==
          "test:1: " + dir.file("act2.xml") +
              ":4: group 1: robot 'robot' has no joint 9 (it has joints 1 to 4)");
    CHECK(lua.integer("#robot:actuation()") == 0);  // a bad file drives nothing

    // a controller file that is a device or a folder is refused, never read
    for (const std::string& target : {std::string("/dev/zero"), dir.path.string()}) {
        gaitlab::test::write_text(dir.file("act3.xml"),
                                  "<gaitlab version=\"1\">\n<actuation>\n<group joints=\"all\">\n"
                                  "<controller file=\"" +
                                      target +
                                      "\"/>\n</group>\n"
                                      "</actuation>\n</gaitlab>\n");
        CHECK(lua.error_of("robot:actuate(assert(gaitlab.actuation.load(DIR .. '/act3.xml')))") ==
              "test:1: " + dir.file("act3.xml") + ":4: controller file " + target +
                  " is not a regular file (a folder, FIFO or device)");
    }

    // a simulation file whose robot file is missing names its resolved path
    gaitlab::test::write_text(dir.file("env.xml"),
                              "<gaitlab version=\"1\"><environment/></gaitlab>");
    gaitlab::test::write_text(dir.file("sim.xml"),
                              "<gaitlab version=\"1\">\n<simulation>\n<environment "
                              "file=\"env.xml\"/>\n<robot file=\"robots/r.xml\"/>\n"
                              "</simulation>\n</gaitlab>\n");
    lua.run("s, err = gaitlab.simulation.load(DIR .. '/sim.xml')");
    CHECK(lua.string("err") == dir.file("sim.xml") +
                                   ":4: simulation/robot[1]: attribute 'file': cannot read " +
                                   dir.file("robots/r.xml") + ": No such file or directory");
}

TEST_CASE("a controller defined inside a script cannot be saved, and says why", "[config_files]") {
    LuaFixture lua;
    lua.run(R"(
        Inline = gaitlab.controller{ name = "inline", step = function(self) end }
        robot = gaitlab.robot.chain{ modules = 2 }
        robot:group("all"):drive(Inline())
    )");
    CHECK(lua.error_of("robot:actuation()") ==
          "test:1: controller 'inline' is defined inside a script (test:2): a file can only "
          "name a controller loaded from its own file (gaitlab.controller.load) or a template");
}

TEST_CASE("errors while a simulation file is built or run name the file and its line",
          "[config_files][lines]") {
    TempDir dir("file_lines");
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    const auto write = [&](const std::string& name, const std::string& inner) {
        gaitlab::test::write_text(dir.file(name),
                                  "<gaitlab version=\"1\">\n" + inner + "\n</gaitlab>\n");
    };
    write("snake.xml", "<robot name=\"snake\"><chain modules=\"3\"/></robot>");
    // everything falls at 1000 m/s² without a floor: the robot diverges at 10 s
    write("falling.xml",
          "<environment gravity=\"0 0 -1000\"><floor enabled=\"false\"/>"
          "</environment>");
    write("sim.xml",
          "<simulation duration=\"20\">\n<environment file=\"falling.xml\"/>\n"
          "<robot file=\"snake.xml\"/>\n<record enabled=\"false\"/></simulation>");
    // run: the engine's error used to name stdlib/simulation.lua:8
    CHECK_THAT(lua.error_of("gaitlab.simulation.run_file(DIR .. '/sim.xml')"),
               Catch::Matchers::StartsWith(dir.file("sim.xml") +
                                           ":2: simulation diverged at t = 10.000 s: body "));

    // an image that is a directory is found when the environment file is read, at the line of
    // its <heightfield> (it was found when the world was compiled, at the simulation file's)
    std::filesystem::create_directory(dir.file("terrain.png"));
    write("hills.xml", "<environment><heightfield image=\"terrain.png\"/></environment>");
    write("sim2.xml",
          "<simulation>\n<environment file=\"hills.xml\"/>\n"
          "<robot file=\"snake.xml\"/></simulation>");
    const std::string image_error = dir.file("hills.xml") +
                                    ":2: environment/heightfield[1]: heightfield 1 cannot read "
                                    "image '" +
                                    dir.file("terrain.png") + "': is a directory";
    lua.run("s, err = gaitlab.simulation.load(DIR .. '/sim2.xml')");
    CHECK(lua.boolean("s == nil"));
    CHECK(lua.string("err") == image_error);
    CHECK(lua.error_of("gaitlab.simulation.run_file(DIR .. '/sim2.xml')") == image_error);

    // two robots of one name: the second <robot> line; a placement of no robot: its <place>
    write("sim3.xml",
          "<simulation>\n<environment file=\"falling.xml\"/>\n"
          "<robot file=\"snake.xml\"/>\n<robot file=\"snake.xml\"/></simulation>");
    lua.run("s, err = gaitlab.simulation.load(DIR .. '/sim3.xml')");
    CHECK(lua.string("err") == dir.file("sim3.xml") +
                                   ":5: two robots named 'snake' (placements name robots: give "
                                   "each its own name)");
    write("placed.xml", "<environment>\n<place robot=\"worm\"/></environment>");
    write("sim4.xml",
          "<simulation>\n<environment file=\"placed.xml\"/>\n"
          "<robot file=\"snake.xml\"/></simulation>");
    lua.run("s, err = gaitlab.simulation.load(DIR .. '/sim4.xml')");
    CHECK(lua.string("err") == dir.file("placed.xml") +
                                   ":3: robot 'worm' is placed but the simulation has no robot "
                                   "of that name");
    // an empty part is line 1; a directory or a device given as a whole file says so
    std::filesystem::create_directory(dir.file("folder.xml"));
    write("empty_ok.xml", "<simulation>\n<environment file=\"empty.xml\"/></simulation>");
    gaitlab::test::write_text(dir.file("empty.xml"), "");
    lua.run("s, err = gaitlab.simulation.load(DIR .. '/empty_ok.xml')");
    CHECK(lua.string("err") ==
          dir.file("empty.xml") +
              ":1: malformed XML: the file holds no element (it is empty, or spaces only)");
    lua.run("s, err = gaitlab.simulation.load(DIR)");
    CHECK(lua.string("err") == dir.path.string() + ": cannot read the file: is a directory");
    lua.run("s, err = gaitlab.world.load('/dev/zero.xml')");
    CHECK(lua.string("err") == "/dev/zero.xml: cannot read the file: No such file or directory");
    lua.run("s, err = gaitlab.world.load(DIR .. '/folder.xml')");
    CHECK(lua.string("err") == dir.file("folder.xml") + ": cannot read the file: is a directory");
    lua.run("s, err = gaitlab.robot.load(DIR)");
    CHECK(lua.string("err") == dir.path.string() + ": cannot read the file: is a directory");
    lua.run("s, err = gaitlab.robot.load_urdf('/dev/zero')");
    CHECK(lua.string("err") ==
          "/dev/zero: cannot read the file: not a regular file (a FIFO, device or socket)");
    lua.run("s, err = gaitlab.actuation.load(DIR)");
    CHECK(lua.string("err") == dir.path.string() + ": cannot read the file: is a directory");
}

TEST_CASE("sim:save never writes outside its folder, whatever the robots are called",
          "[config_files][save]") {
    TempDir dir("save_names");
    std::filesystem::create_directory(dir.file("out"));
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run(R"(
        world = gaitlab.world()
        names = { "../../evil", "/etc/gaitlab_x", "a/b", "a_b", ".hidden", "serpent à sonnettes",
                  string.rep("é", 100), "back\\slash", "ok" }
        for i, name in ipairs(names) do
          local r = gaitlab.robot.chain{ name = name, modules = 2 }
          world:add(r, { y = i })
          r:group("all"):drive(gaitlab.controllers.sine{})
        end
        sim = gaitlab.simulation{ world = world }
        saved = assert(sim:save(DIR .. "/out/s.xml"))
        loaded, setup = assert(gaitlab.simulation.load(DIR .. "/out/s.xml"))
    )");
    // the folder holds everything; nothing was written next to it or above it
    std::vector<std::string> files, outside;
    for (const auto& e : std::filesystem::directory_iterator(dir.file("out")))
        files.push_back(e.path().filename().string());
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir.path)) {
        if (e.path().parent_path() != dir.path / "out" && e.path() != dir.path / "out") {
            outside.push_back(e.path().string());
        }
    }
    CHECK(outside.empty());
    CHECK_FALSE(std::filesystem::exists("/etc/gaitlab_x.robot.xml"));
    std::sort(files.begin(), files.end());
    CHECK(files.size() == 2 + 2 * 9);
    for (const char* f :
         {"s.______evil.robot.xml", "s._etc_gaitlab_x.robot.xml", "s.a_b.robot.xml",
          "s.a_b_2.robot.xml", "s._hidden.robot.xml", "s.serpent_à_sonnettes.robot.xml",
          "s.back_slash.actuation.xml", "s.ok.robot.xml"}) {
        CHECK(std::find(files.begin(), files.end(), f) != files.end());
    }
    // 100 two-byte characters cut to 64 bytes, between characters
    const std::string e32 = [] {
        std::string s;
        for (int i = 0; i < 32; ++i)
            s += "é";
        return s;
    }();
    CHECK(std::find(files.begin(), files.end(), "s." + e32 + ".robot.xml") != files.end());
    // and the robots come back under their own names
    CHECK(lua.boolean("setup.robots['../../evil'] ~= nil"));
    CHECK(lua.boolean("setup.robots['/etc/gaitlab_x'] ~= nil"));
    CHECK(lua.boolean("setup.robots['a/b'] ~= nil and setup.robots['a_b'] ~= nil"));
    CHECK(lua.integer("#setup.controllers['a/b']") == 1);
}

TEST_CASE("saves make the folders they need and name the file as the script gave it",
          "[config_files][save]") {
    TempDir dir("save_folders");
    namespace fs = std::filesystem;
    fs::create_directories(dir.file("proj/parts/s.snake.robot.xml"));  // a folder in the way
    gaitlab::test::write_text(dir.file("proj/blocker"), "a file where a folder must go");
    // a script file: relative paths are relative to its folder, and shown as it wrote them
    gaitlab::test::write_text(dir.file("proj/save.lua"), std::string(kSavedSnake) + R"(
        ok = {
          sim = both(sim:save("runs/x/sim.xml")),
          robot = both(robot:save("robots/a/b/snake.xml")),
          act = both(robot:actuation():save("acts/snake.xml")),
          world = both(world:save("worlds/w.xml")),
          urdf = both(robot:save_urdf("urdf/deep/snake.urdf")),
          template = both(gaitlab.controller.write_template("sine", "ctl/new/mine.lua")),
        }
        bad = {
          sim = both(sim:save("blocker/x/sim.xml")),
          robot = both(robot:save("blocker/snake.xml")),
          act = both(robot:actuation():save("./blocker/a/b.xml")),
          world = both(world:save("robots")),
          urdf = both(robot:save_urdf("blocker/u.urdf")),
          template = both(gaitlab.controller.write_template("sine", "blocker/mine.lua")),
          part = both(sim:save("parts/s.xml")),
          absolute = both(robot:save(DIR .. "/proj/blocker/abs.xml")),
        }
    )");
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run("dofile(DIR .. '/proj/save.lua')");
    const std::string proj = dir.file("proj");
    CHECK(lua.string("ok.sim[1]") == proj + "/runs/x/sim.xml");
    for (const char* f :
         {"runs/x/sim.xml", "runs/x/sim.snake.robot.xml", "runs/x/sim.snake.actuation.xml",
          "runs/x/sim.environment.xml", "robots/a/b/snake.xml", "acts/snake.xml", "worlds/w.xml",
          "urdf/deep/snake.urdf", "ctl/new/mine.lua"}) {
        INFO(f);
        CHECK(fs::is_regular_file(proj + "/" + f));
    }
    CHECK(lua.string("ok.template[1]") == proj + "/ctl/new/mine.lua");
    lua.run("loaded = assert(gaitlab.simulation.load(DIR .. '/proj/runs/x/sim.xml'))");

    const std::string in_way = ": cannot create folder blocker: a file of that name is in the way";
    CHECK(lua.boolean("bad.sim[1] == nil"));
    CHECK(lua.string("bad.sim[2]") == "cannot write blocker/x/sim.xml" + in_way);
    CHECK(lua.string("bad.robot[2]") == "cannot write blocker/snake.xml" + in_way);
    CHECK(lua.string("bad.act[2]") == "cannot write ./blocker/a/b.xml" + in_way);
    CHECK(lua.string("bad.world[2]") == "cannot write robots: is a directory");
    CHECK(lua.string("bad.urdf[2]") == "cannot write blocker/u.urdf" + in_way);
    CHECK(lua.string("bad.template[2]") == "cannot write blocker/mine.lua" + in_way);
    // a part that fails is named after the save it belongs to
    CHECK(lua.string("bad.part[2]") ==
          "cannot write parts/s.xml: its part parts/s.snake.robot.xml: is a directory");
    // an absolute path is shown as given, folders too
    CHECK(lua.string("bad.absolute[2]") == "cannot write " + proj +
                                               "/blocker/abs.xml: cannot create folder " + proj +
                                               "/blocker: a file of that name is in the way");
    // a folder that may not be written (root may write anywhere: checked for other users)
    if (::geteuid() != 0) {
        fs::create_directories(dir.file("proj/ro"));
        fs::permissions(dir.file("proj/ro"), fs::perms::owner_read | fs::perms::owner_exec);
        gaitlab::test::write_text(dir.file("proj/ro.lua"), R"(
            ro = { sim = { sim:save("ro/sim.xml") }, robot = { robot:save("ro/sub/x.xml") } }
        )");
        lua.run("dofile(DIR .. '/proj/ro.lua')");
        fs::permissions(dir.file("proj/ro"), fs::perms::owner_all);
        CHECK(lua.string("ro.sim[2]") == "cannot write ro/sim.xml: Permission denied");
        CHECK(lua.string("ro.robot[2]") ==
              "cannot write ro/sub/x.xml: cannot create folder ro/sub: Permission denied");
    }
    // no temporary file left anywhere
    for (const auto& e : fs::recursive_directory_iterator(dir.path)) {
        INFO(e.path());
        CHECK(e.path().filename().string().find(".tmp-") == std::string::npos);
    }
}

TEST_CASE("a robot URDF cannot hold is nil and a message naming why", "[config_files][save]") {
    // save_urdf raised an error that ended the script, and a robot joined a to b and b to a was
    // said to be "not connected"
    TempDir dir("save_urdf_tree");
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run(R"(
        local function body(name, x)
          return { name = name, size = {0.05, 0.05, 0.05}, mass = 0.1, position = {x, 0, 0.03} }
        end
        local function joint(name, parent, child)
          return { name = name, parent = parent, child = child, pivot = {0.025, 0, 0.03},
                   axis = {0, 1, 0} }
        end
        loop = gaitlab.robot.new{ name = "loop", bodies = { body("a", 0), body("b", 0.05) },
                                  joints = { joint("ab", "a", "b"), joint("ba", "b", "a") } }
        apart = gaitlab.robot.new{ name = "apart",
                                   bodies = { body("a", 0), body("b", 0.05), body("c", 0.3) },
                                   joints = { joint("ab", "a", "b") } }
        looped = { loop:save_urdf(DIR .. "/loop.urdf") }
        parted = { apart:save_urdf(DIR .. "/apart.urdf") }
    )");
    CHECK(lua.boolean("looped[1] == nil and parted[1] == nil"));
    CHECK(lua.string("looped[2]") ==
          dir.file("loop.urdf") +
              ": robot 'loop' has a loop of joints: every body hangs from one, so none is the "
              "root (URDF needs a tree)");
    CHECK(lua.string("parted[2]") ==
          dir.file("apart.urdf") +
              ": robot 'apart' is not connected: bodies 'a', 'c' hang from no joint (URDF needs "
              "a single root body)");
    CHECK_FALSE(std::filesystem::exists(dir.file("loop.urdf")));
}

TEST_CASE("load_urdf takes its links' inertia from the file or from their shapes",
          "[config_files]") {
    TempDir dir("urdf_inertia");
    // a placeholder inertia about the link origin, 10 cm behind the box's centre: outside it
    const auto worm = [](const char* at) {
        return std::string(
                   "<robot name=\"worm\">\n<link name=\"a\"><inertial><mass "
                   "value=\"0.05\"/>\n<inertia ixx=\"1e-5\" iyy=\"1e-5\" "
                   "izz=\"1e-5\"/></inertial><collision><origin xyz=\"") +
               at +
               "\"/><geometry><box size=\"0.08 0.05 0.03\"/></geometry></collision></link>\n"
               "</robot>\n";
    };
    gaitlab::test::write_text(dir.file("worm.urdf"), worm("0.1 0 0"));
    // 4 cm behind: on the box's -x face, its body's centre of mass
    gaitlab::test::write_text(dir.file("inside.urdf"), worm("0.04 0 0"));
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run(R"(
        refused = { gaitlab.robot.load_urdf(DIR .. "/worm.urdf") }
        given = { gaitlab.robot.load_urdf(DIR .. "/worm.urdf", { inertia = "file" }) }
        worm = gaitlab.robot.load_urdf(DIR .. "/worm.urdf", { inertia = "shapes" })
        moments = worm:bodies()[1].inertia
        inside = gaitlab.robot.load_urdf(DIR .. "/inside.urdf"):bodies()[1]
        centred = worm:bodies()[1].com
    )");
    CHECK(lua.number("inside.com.x") == Approx(-0.04));
    CHECK(lua.boolean("inside.com.y == 0 and inside.com.z == 0 and inside.inertia.x == 1e-5"));
    CHECK(lua.boolean("centred.x == 0 and centred.y == 0 and centred.z == 0"));
    CHECK(lua.boolean("refused[1] == nil and given[1] == nil and refused[2] == given[2]"));
    CHECK_THAT(lua.string("refused[2]"),
               Catch::StartsWith(dir.file("worm.urdf") +
                                 ":2: robot/link[1]/inertial[1]: robot 'worm' body 'a' com must "
                                 "lie inside the box") &&
                   Catch::EndsWith("(gaitlab.robot.load_urdf(path, { inertia = \"shapes\" }))"));
    // the uniform box of 50 g: m (y² + z²) / 12 about x
    CHECK(lua.number("moments.x") == Approx(0.05 * (0.05 * 0.05 + 0.03 * 0.03) / 12));
    CHECK(lua.number("moments.z") == Approx(0.05 * (0.08 * 0.08 + 0.05 * 0.05) / 12));
    CHECK_THAT(lua.error_of("gaitlab.robot.load_urdf(DIR .. '/worm.urdf', { inertia = 'shape' })"),
               Catch::Contains("bad argument #2 to 'load_urdf' (field 'inertia': \"file\" "
                               "(each link's <inertial> as the file gives it) or \"shapes\""));
    CHECK_THAT(lua.error_of("gaitlab.robot.load_urdf(DIR .. '/worm.urdf', { inertia = 'shape' })"),
               Catch::EndsWith("got \"shape\"; did you mean 'shapes'?)"));
    CHECK_THAT(lua.error_of("gaitlab.robot.load_urdf(DIR .. '/worm.urdf', { inertias = 'file' })"),
               Catch::Contains("unknown key 'inertias'"));
    CHECK_THAT(lua.error_of("gaitlab.robot.load_urdf(DIR .. '/worm.urdf', 'shapes')"),
               Catch::Contains("bad argument #2 to 'load_urdf'"));
}

TEST_CASE("a save that fails changes nothing on disk", "[config_files][save]") {
    // the parts were written one by one before the simulation file: a simulation file that
    // could not be written (a folder of that name) still replaced the user's robot file beside it
    TempDir dir("save_all_or_none");
    namespace fs = std::filesystem;
    fs::create_directories(dir.file("walk.xml"));
    gaitlab::test::write_text(dir.file("walk.snake.robot.xml"), "my own robot file");
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run(std::string(kSavedSnake) + R"(
        folder = both(sim:save(DIR .. "/walk.xml"))
        empty = both(sim:save(""))
        dot = both(sim:save(DIR .. "/."))
        slash = both(sim:save(DIR .. "/sub/"))
    )");
    CHECK(lua.boolean("folder[1] == nil"));
    CHECK(lua.string("folder[2]") == "cannot write " + dir.file("walk.xml") + ": is a directory");
    CHECK(gaitlab::test::read_text(dir.file("walk.snake.robot.xml")) == "my own robot file");
    for (const char* name : {"empty", "dot", "slash"}) {
        INFO(name);
        CHECK(lua.boolean(std::string(name) + "[1] == nil"));
        CHECK_THAT(lua.string(std::string(name) + "[2]"),
                   Catch::Contains(": a file name expected, as in walk.xml"));
    }
    // nothing else was made: no parts, no hidden files, no temporary files
    std::vector<std::string> left;
    for (const auto& e : fs::recursive_directory_iterator(dir.path))
        left.push_back(fs::relative(e.path(), dir.path).string());
    std::sort(left.begin(), left.end());
    CHECK(left == std::vector<std::string>{"walk.snake.robot.xml", "walk.xml"});
    CHECK_FALSE(fs::exists(".environment.xml"));
}

TEST_CASE("an actuation file that drives the same joints twice names the file and line",
          "[config_files]") {
    TempDir dir("act_twice");
    const std::string act = dir.file("twice.actuation.xml");
    gaitlab::test::write_text(act, R"(<?xml version="1.0"?>
<gaitlab version="1">
    <actuation>
        <group joints="pitch">
            <controller builtin="sine" amplitude="30"/>
        </group>
        <group joints="all">
            <controller builtin="offset" angle="5"/>
        </group>
        <group joints="5 1 3">
            <controller builtin="offset" angle="10"/>
        </group>
    </actuation>
</gaitlab>
)");
    LuaFixture lua;
    lua.run("DIR = '" + dir.path.string() + "'");
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 5, connection = "pitch-yaw" }
        act = assert(gaitlab.actuation.load(DIR .. "/twice.actuation.xml"))
    )");
    const std::string why =
        "group 3: controller 'offset' cannot drive joints 1, 3, 5 of robot 'snake': controller "
        "'sine' already drives exactly these joints (one controller per group: their targets "
        "would add up; groups that only partly overlap do add)";
    // the line of the group's <controller>
    CHECK(lua.error_of("robot:actuate(act)") == "test:1: " + act + ":11: " + why);
    CHECK(lua.integer("#robot:actuation():groups()") == 0);  // nothing half applied
    // with what already drives the robot: the same joints given in Lua first
    lua.run("robot:group{ 3, 1, 5 }:drive(gaitlab.controllers.sine{})");
    CHECK_THAT(lua.error_of("robot:actuate(act)"),
               Catch::Contains(act + ":5: group 1: controller 'sine' cannot drive joints 1, 3, 5 "
                                     "of robot 'snake': controller 'sine' already drives"));
    // and in a simulation file: nil and the message
    lua.run(R"(
        r2 = gaitlab.robot.chain{ name = "snake", modules = 5, connection = "pitch-yaw" }
        w = gaitlab.world()
        w:add(r2)
        assert(gaitlab.simulation{ world = w }:save(DIR .. "/sim.xml"))
    )");
    std::string text = gaitlab::test::read_text(dir.file("sim.xml"));
    const std::string robot_attr = "<robot file=\"sim.snake.robot.xml\"";
    REQUIRE(text.find(robot_attr) != std::string::npos);
    text.replace(text.find(robot_attr), robot_attr.size(),
                 robot_attr + " actuation=\"twice.actuation.xml\"");
    gaitlab::test::write_text(dir.file("sim.xml"), text);
    lua.run("s, err = gaitlab.simulation.load(DIR .. '/sim.xml')");
    CHECK(lua.boolean("s == nil"));
    CHECK(lua.string("err") == act + ":11: " + why);
}
