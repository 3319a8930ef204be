// gaitlab.data (scripting/src/wrap_data.cpp): opening run folders, series by name and by kind +
// value + joint, time ranges, events, export, plots, and live buffers (sim:live).
#include <catch2/catch.hpp>

#include <filesystem>

#include <fmt/format.h>

#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::test::LuaFixture;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;
namespace fs = std::filesystem;

namespace {

// a recorded 1 s run of a 4-module snake; DIR is a global of the fixture
void record(LuaFixture& lua, const TempDir& tmp) {
    lua.run("DIR = '" + tmp / "run" + "'");
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30 })
        sim = gaitlab.simulation{ world = world, record = DIR }
        sim:run(0.5)
        ctl.amplitude = 35
        ctl:set("frequency", 1, "console")
        sim:run(0.5)
        sim:record(false)
    )");
}

// a world w3 with a 3-module "worm" and no controller
void robot_only(LuaFixture& lua) {
    lua.run("w3 = gaitlab.world() w3:add(gaitlab.robot.chain{ name = 'worm', modules = 3 })");
}

}  // namespace

TEST_CASE("a run folder opens and gives its series", "[wrap_data]") {
    TempDir tmp("wrap_data_open");
    LuaFixture lua;
    record(lua, tmp);
    lua.run("run = assert(gaitlab.data.open(DIR))");
    CHECK(lua.string("run.status") == "finished");
    CHECK(lua.integer("run.rows") == 34);
    CHECK(lua.boolean("run.truncated") == false);
    CHECK(lua.string("run.dir") == tmp / "run");
    CHECK(lua.integer("#run:series()") == 80);
    CHECK(lua.string("run:series()[1].name") == "snake.com.x");
    CHECK(lua.string("run:series()[1].unit") == "m");
    lua.run("s = run:get('sine.amplitude')");
    CHECK(lua.integer("#s.time") == 34);
    CHECK(lua.number("s.values[1]") == 30);
    CHECK(lua.number("s.values[34]") == 35);
    CHECK(lua.string("s.kind") == "controller");
    CHECK(lua.string("s.unit") == "deg");
    lua.run("j = run:get{ kind = 'robot', value = 'angle', joint = 2 }");
    CHECK(lua.string("j.name") == "snake.angle[2]");
    CHECK(lua.integer("j.joint") == 2);
    lua.run("r = run:get('snake.com.x', { from = 0.3, to = 0.6 })");
    CHECK(lua.integer("#r.time") == 11);
    CHECK(lua.number("r.time[1]") == Approx(0.3));
    CHECK(lua.integer("#run:select('snake.angle[*]')") == 4);
    lua.run("ev = run:events()");
    CHECK(lua.integer("#ev") == 2);
    CHECK(lua.string("ev[1].origin") == "script");
    CHECK(lua.string("ev[2].origin") == "console");
    CHECK(lua.string("ev[2].name") == "sine.frequency");
    CHECK(lua.integer("ev[2].tick") == 500);
    CHECK(lua.number("ev[2].time") == Approx(0.5));
    CHECK_THAT(lua.string("run:log()"), Catch::Contains("recording finished at t = 1 s: 34 rows"));
    CHECK(lua.string("run.provenance.lua") == "Lua 5.4.4");
    CHECK_THAT(lua.string("tostring(run)"), Catch::EndsWith("(80 series, finished)"));

    const std::string bad = "test:1: bad argument #1 to 'get' (";
    CHECK(lua.error_of("run:get('snake.angle[7]')") ==
          bad +
              "unknown series 'snake.angle[7]'; did you mean 'snake.angle[1]', "
              "'snake.angle[2]' or 'snake.angle[3]'?)");
    CHECK(lua.error_of("run:get{ kind = 'robot', value = 'angel', joint = 2 }") ==
          bad + "no robot series 'angel' of joint 2; did you mean 'angle'?)");
    CHECK(lua.error_of("run:get{ kind = 'robots', value = 'angle' }") ==
          bad +
              "field 'kind': 'robot', 'controller', 'sensor' or 'object' expected, got 'robots')");
    CHECK(lua.error_of("run:get(3)") ==
          bad + "series name or {kind =, value =, joint =} expected, got number)");
    CHECK(lua.error_of("run:get('snake.com.x', { form = 1 })") ==
          "test:1: bad argument #2 to 'get' (unknown key 'form'; did you mean 'from'?)");
}

TEST_CASE("a folder that is not a run gives nil and a message", "[wrap_data]") {
    TempDir tmp("wrap_data_missing");
    LuaFixture lua;
    lua.run("DIR = '" + tmp.str() + "'");
    lua.run("r, err = gaitlab.data.open(DIR)");
    CHECK(lua.boolean("r == nil"));
    CHECK(lua.string("err") == tmp.str() +
                                   " is not a run folder: it has no run.json, series.csv and "
                                   "data.csv (a run folder holds run.json, series.csv, "
                                   "data.csv, events.csv, log.txt and config/)");
    CHECK(lua.error_of("gaitlab.data.open()") ==
          "test:1: bad argument #1 to 'open' (string expected, got no value)");
}

TEST_CASE("series export to one file or one file each", "[wrap_data]") {
    TempDir tmp("wrap_data_export");
    LuaFixture lua;
    record(lua, tmp);
    lua.run("OUT = '" + tmp.str() + "'");
    lua.run("run = gaitlab.data.open(DIR)");
    lua.run("files = run:export{ series = { 'snake.com.*' }, dir = OUT .. '/each', to = 0.1 }");
    CHECK(lua.integer("#files") == 6);
    CHECK(read_text(tmp / "each/snake.com.vz.csv").rfind("time,snake.com.vz\n0,0\n0.03,", 0) == 0);
    lua.run("run:export{ series = 'sine.amplitude', file = OUT .. '/one.csv' }");
    const std::string one = read_text(tmp / "one.csv");
    CHECK(one.rfind("time,sine.amplitude\n0,30\n", 0) == 0);
    CHECK(lua.error_of("run:export{ series = 'sine.amplitude' }") ==
          "test:1: bad argument #1 to 'export' (field 'file': give either file = or dir =)");
}

TEST_CASE("run:plot draws a path with x and y", "[wrap_data]") {
    TempDir tmp("wrap_data_path");
    LuaFixture lua;
    record(lua, tmp);
    lua.run("OUT = '" + tmp.str() + "'");
    lua.run(R"(
        run = gaitlab.data.open(DIR)
        png, gp, csv = run:plot{ x = "snake.com.x", y = "snake.com.y", output = OUT .. "/p/path.png",
                                 from = 0.1 }
    )");
    CHECK(lua.string("png") == tmp / "p/path.png");
    CHECK(std::filesystem::file_size(tmp / "p/path.png") > 3000);
    CHECK(read_text(tmp / "p/path.csv").rfind("time,snake.com.x,snake.com.y\n0.12,", 0) == 0);
    CHECK(read_text(tmp / "p/path.gp").find("using 2:3") != std::string::npos);
    const std::string bad = "test:1: bad argument #1 to 'plot' (";
    CHECK(lua.error_of("run:plot{ x = 'snake.com.x', output = OUT .. '/q.png' }") ==
          bad + "a path plot needs two series: x and y)");
    CHECK(lua.error_of("run:plot{ x = 'snake.com.x', y = 'snake.com.y', series = 'snake.com.z', "
                       "output = OUT .. '/q.png' }") ==
          bad +
              "a plot shows series against time or one series against another (x and y), not "
              "both)");
    CHECK(lua.error_of("run:plot{ output = OUT .. '/q.png' }") ==
          bad + "field 'series': a series name or a list of names expected, got nil)");
}

TEST_CASE("recording options: folder, rows, series, a late start and a stop", "[wrap_data]") {
    TempDir tmp("wrap_data_options");
    LuaFixture lua;
    lua.run("OUT = '" + tmp.str() + "'");
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "worm", modules = 3 }
        world = gaitlab.world()
        world:add(robot)
        robot:group("all"):drive(gaitlab.controllers.sine{})
        a = gaitlab.simulation{ world = world,
              record = { dir = OUT .. '/a', record_every = 10, flush_seconds = 0,
                         series = { 'worm.com.*', 'controller' } } }
        a:run(0.1)
        robot2 = gaitlab.robot.chain{ name = "worm", modules = 3 }
        world2 = gaitlab.world()
        world2:add(robot2)
        robot2:group("all"):drive(gaitlab.controllers.sine{})
        b = gaitlab.simulation{ world = world2, record = false }
        b:run(0.05)
        dir_b = b:record(OUT .. '/b')
        b:run(0.05)
        b:record(false)
        b:run(0.05)
    )");
    CHECK(lua.string("a.record_dir") == tmp / "a");
    CHECK(lua.string("dir_b") == tmp / "b");
    CHECK(lua.boolean("b.record_dir == nil"));
    lua.run("ra = gaitlab.data.open(OUT .. '/a') rb = gaitlab.data.open(OUT .. '/b')");
    CHECK(lua.integer("#ra:series()") == 6 + 5 + 2 * 3);
    CHECK(lua.integer("ra.rows") == 11);
    CHECK(lua.integer("rb.rows") == 3);  // at 0.05 s, then 0.08 and ... up to 0.1 s
    CHECK(lua.number("rb:get('worm.com.x').time[1]") == Approx(0.05));
    CHECK(lua.error_of("a:record(OUT .. '/c')") == "test:1: the simulation already records into " +
                                                       (tmp / "a") +
                                                       " (sim:record(false) stops that)");
    robot_only(lua);
    CHECK(lua.error_of("gaitlab.simulation{ world = w3, record = { dir = OUT .. '/d', "
                       "series = { 'worm.angel[1]' } } }") ==
          "test:1: bad argument #1 to 'simulation' (field 'record': no series matches "
          "'worm.angel[1]'; did you mean 'worm.angle[1]', 'worm.angle[2]' or 'worm.angle[3]'?)");
    // a folder under a regular file cannot be made: a plain error naming it
    lua.run("io.open(OUT .. '/file', 'w'):close()");
    CHECK_THAT(lua.error_of("gaitlab.simulation{ world = w3, record = OUT .. '/file/run' }"),
               Catch::StartsWith("test:1: cannot create run folder " + (tmp / "file/run") +
                                 ": Not a directory"));
    CHECK(lua.error_of("ctl = gaitlab.controllers.sine{} ctl:set('amplitude', 3, 'repl')") ==
          "test:1: bad argument #3 to 'set' ('script', 'console' or 'viewer' expected, got "
          "'repl')");
    CHECK(lua.error_of("ctl:set('amplitud', 3)") ==
          "test:1: bad argument #1 to 'set' (controller 'sine' has no parameter 'amplitud'; did "
          "you mean 'amplitude'?)");
}

TEST_CASE("two simulations of a script never share a run folder", "[wrap_data]") {
    TempDir tmp("wrap_data_shared");
    LuaFixture lua;
    lua.run("OUT = '" + tmp.str() + "'");
    lua.run(R"(
        function sim(n, record)
          local w = gaitlab.world()
          w:add(gaitlab.robot.chain{ name = "worm" .. n, modules = 2 })
          return gaitlab.simulation{ world = w, record = record }
        end
        a = sim(1, OUT .. "/run")
        a:run(0.3)
    )");
    const std::string refused =
        "cannot record into {}: simulation 1 of this script recorded "
        "into it (give each simulation its own folder)";
    // the same folder, by the same or another name, at creation or with sim:record
    // (test:5 is the line of gaitlab.simulation in sim)
    CHECK(lua.error_of("b = sim(2, OUT .. '/run')") ==
          "test:5: " + fmt::format(refused, tmp / "run"));
    CHECK(lua.error_of("b = sim(2, OUT .. '/x/../run/')") ==
          "test:5: " + fmt::format(refused, tmp / "x/../run/"));
    lua.run("b = sim(2, false)");
    CHECK(lua.error_of("b:record(OUT .. '/run')") ==
          "test:1: " + fmt::format(refused, tmp / "run"));
    // also once the first has stopped, and the simulation itself a second time
    lua.run("a:record(false)");
    CHECK(lua.error_of("b:record(OUT .. '/run')") ==
          "test:1: " + fmt::format(refused, tmp / "run"));
    CHECK(lua.error_of("a:record(OUT .. '/run')") ==
          "test:1: cannot record into " + (tmp / "run") +
              ": simulation 1 of this script recorded into it already (give each simulation its "
              "own folder)");
    lua.run("b:record(OUT .. '/run-b') b:run(0.1)");
    // the first run is whole
    lua.run("r = gaitlab.data.open(OUT .. '/run')");
    CHECK(lua.string("r.status") == "finished");
    CHECK(lua.string("r.state") == "finished");
    CHECK(lua.integer("r.rows") == 11);
    CHECK(lua.string("r:series()[1].name") == "worm1.com.x");
}

TEST_CASE("the host's run folders skip the ones a script took", "[wrap_data]") {
    TempDir tmp("wrap_data_host_dirs");
    LuaFixture lua;
    gaitlab::scripting::RecordSettings s;
    s.by_default = true;
    s.dir = tmp / "run";
    lua.host.set_recording(s);
    lua.run("OUT = '" + tmp.str() + "'");
    lua.run(R"(
        local function world(n)
          local w = gaitlab.world()
          w:add(gaitlab.robot.chain{ name = "worm" .. n, modules = 2 })
          return w
        end
        gaitlab.simulation{ world = world(1), record = OUT .. "/run-2" }:run(0.1)
        gaitlab.simulation{ world = world(2) }:run(0.1)
        gaitlab.simulation{ world = world(3) }:run(0.1)
    )");
    lua.host.finish();
    const std::vector<std::string> folders = lua.host.run_folders();
    CHECK(folders == std::vector<std::string>{tmp / "run-2", tmp / "run", tmp / "run-3"});
    lua.run("r = gaitlab.data.open(OUT .. '/run-2')");
    CHECK(lua.string("r:series()[1].name") == "worm1.com.x");
}

TEST_CASE("a refused recording leaves no folder the host made for it", "[wrap_data]") {
    TempDir tmp("wrap_data_refused");
    LuaFixture lua;
    gaitlab::scripting::RecordSettings s;
    s.by_default = true;
    s.root = tmp / "runs";
    s.name = "bad";
    lua.host.set_recording(s);
    lua.run("OUT = '" + tmp.str() + "'");
    robot_only(lua);
    const auto runs = [&] {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(tmp / "runs"))
            names.push_back(e.path().filename().string());
        return names;
    };
    // refused by the recorder, at creation and with sim:record, after the host made the folder
    // (and its root)
    CHECK_THAT(lua.error_of("gaitlab.simulation{ world = w3, record = { series = { 'worm.angel[*]' "
                            "} } }"),
               Catch::StartsWith("test:1: bad argument #1 to 'simulation' (field 'record': no "
                                 "series matches 'worm.angel[*]'"));
    lua.run("sim = gaitlab.simulation{ world = w3, record = false }");
    CHECK_THAT(lua.error_of("sim:record{ series = { 'nothing' } }"),
               Catch::StartsWith("test:1: bad argument #1 to 'record' (no series matches"));
    // refused by the binding, before a folder is made
    CHECK_THAT(lua.error_of("sim:record{ record_every = -1 }"),
               Catch::StartsWith("test:1: bad argument #1 to 'record' (record_every must be"));
    CHECK(!fs::exists(tmp / "runs"));  // nor the root it made for them
    // a folder the script names stays, empty as it was
    fs::create_directories(tmp / "mine");
    CHECK_THAT(lua.error_of("sim:record{ dir = OUT .. '/mine', series = { 'nothing' } }"),
               Catch::StartsWith("test:1: bad argument #1 to 'record' (no series matches"));
    CHECK(fs::is_directory(tmp / "mine"));
    CHECK(fs::is_empty(tmp / "mine"));
    // the next recording gets a folder as usual
    lua.run("dir = sim:record(true) sim:run(0.1) sim:record(false)");
    CHECK(runs().size() == 1);
    CHECK(lua.string("dir") == tmp / ("runs/" + runs()[0]));
    CHECK(fs::exists(tmp / ("runs/" + runs()[0] + "/run.json")));
    // a root that was there stays, even empty
    fs::create_directories(tmp / "root");
    s.root = tmp / "root";
    lua.host.set_recording(s);
    CHECK_THAT(lua.error_of("sim:record{ series = { 'nothing' } }"),
               Catch::StartsWith("test:1: bad argument #1 to 'record' (no series matches"));
    CHECK(fs::is_directory(tmp / "root"));
    CHECK(fs::is_empty(tmp / "root"));
    // a root where no folder can be made: the error names the folder
    lua.run("io.open(OUT .. '/file', 'w'):close()");
    s.root = tmp / "file";
    lua.host.set_recording(s);
    CHECK_THAT(lua.error_of("sim:record(true)"),
               Catch::StartsWith("test:1: cannot create run folder " + (tmp / "file/bad-")) &&
                   Catch::EndsWith(": Not a directory"));
}

TEST_CASE("a split export of hostile series names stays inside its folder", "[wrap_data]") {
    TempDir tmp("wrap_data_hostile");
    LuaFixture lua;
    lua.run("OUT = '" + tmp.str() + "'");
    lua.run(R"(
        local w = gaitlab.world()
        w:add(gaitlab.robot.chain{ name = "../../-x", modules = 2 })
        gaitlab.simulation{ world = w, record = { dir = OUT .. "/run", series = { "robot" } } }:run(0.1)
        run = gaitlab.data.open(OUT .. "/run")
        files = run:export{ series = "robot", dir = OUT .. "/each" }
    )");
    CHECK(lua.string("files[1]") == tmp / "each/_.._.._-x.com.x.csv");
    for (const auto& e : fs::directory_iterator(tmp.path)) {
        const std::string name = e.path().filename().string();
        CHECK((name == "run" || name == "each"));
    }
    CHECK(lua.integer("#files") ==
          static_cast<long long>(
              std::distance(fs::directory_iterator(tmp / "each"), fs::directory_iterator())));
}

TEST_CASE("live buffers keep the latest samples of chosen series", "[wrap_data]") {
    LuaFixture lua;
    lua.run(R"(
        robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
        world = gaitlab.world()
        world:add(robot)
        robot:group("pitch"):drive(gaitlab.controllers.sine{})
        sim = gaitlab.simulation{ world = world }
        live = sim:live{ series = { 'snake.com.x', 'sine.angle[1]' }, sample_every = 10,
                         refresh = 0, size = 5 }
        sim:run(0.2)
        x = live:get('snake.com.x')
        all = live:get()
    )");
    CHECK(lua.integer("#x.time") == 5);
    CHECK(lua.number("x.time[5]") == Approx(0.2));
    CHECK(lua.number("x.time[1]") == Approx(0.16));
    CHECK(lua.integer("#all['sine.angle[1]']") == 5);
    CHECK(lua.integer("live.size") == 5);
    CHECK(lua.integer("live.sample_every") == 10);
    CHECK(lua.integer("live.version") == 20);
    lua.run("live.size = 3  live.sample_every = 30  sim:run(0.3)");
    CHECK(lua.integer("#live:get('snake.com.x').time") == 3);
    // samples at multiples of 30 ticks: 0.42, 0.45, 0.48 s
    CHECK(lua.number("live:get('snake.com.x').time[3]") == Approx(0.48));
    CHECK(lua.number("live:get('snake.com.x').time[1]") == Approx(0.42));
    CHECK(lua.error_of("live.size = 0") == "test:1: size must be in [1, 10000000] samples (got 0)");
    // beyond an int: the number as given (it was refused as -727379968)
    CHECK(lua.error_of("live.size = 1e12") ==
          "test:1: size must be in [1, 10000000] samples (got 1000000000000)");
    CHECK(lua.error_of("sim:live{ size = 1e12 }") ==
          "test:1: bad argument #1 to 'live' (size must be in [1, 10000000] samples (got "
          "1000000000000))");
    CHECK(lua.error_of("live.sample_every = 2^40") ==
          "test:1: sample_every must be in [1, 1000000000] ticks (got 1099511627776)");
    CHECK(lua.error_of("live.colour = 1") == "test:1: live buffers have no setting 'colour'");
    CHECK(lua.error_of("live:get('snake.com.y')") ==
          "test:1: bad argument #1 to 'get' (the live buffers keep no series 'snake.com.y'; did "
          "you mean 'snake.com.x'?)");
    CHECK(lua.error_of("sim:live{ size = 1, sample_every = 0 }") ==
          "test:1: bad argument #1 to 'live' (field 'sample_every': at least 1 expected)");
    // publications come every `refresh` s of wall time, but what a script reads after a run
    // ends at its last sample (it ended at the last publication, seconds behind)
    lua.run(R"(
        slow = sim:live{ series = { 'snake.com.x' }, sample_every = 10, refresh = 1000,
                         size = 500 }
        sim:run(0.5)
        slow_x = slow:get('snake.com.x')
    )");
    CHECK(lua.number("slow_x.time[#slow_x.time]") == Approx(lua.number("sim.time")));
    CHECK(lua.integer("#slow_x.time") == 50);
}

TEST_CASE("a Lua controller's parameters and values are recorded like a built-in's",
          "[wrap_data]") {
    TempDir tmp("wrap_data_lua");
    LuaFixture lua;
    lua.run("DIR = '" + tmp / "run" + "'");
    lua.run("FILE = '" GAITLAB_SOURCE_DIR "/examples/controllers/my_sine.lua'");
    lua.run(R"(
        local MySine = gaitlab.controller.load(FILE)
        robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
        world = gaitlab.world()
        world:add(robot)
        ctl = robot:group("pitch"):drive(MySine{ amplitude = 30 })
        sim = gaitlab.simulation{ world = world, record = DIR }
        sim:run(0.51)  -- the last row (0.51 s) holds the values of the last control step
        sim:record(false)
        run = gaitlab.data.open(DIR)
        t = run:get("my_sine.time[4]")
        a = run:get("my_sine.angle[2]")
    )");
    CHECK(lua.number("t.values[#t.values]") == lua.number("ctl:values().time[4]"));
    CHECK(lua.number("a.values[#a.values]") == lua.number("ctl:values().angle[2]"));
    CHECK(lua.string("run:get('my_sine.frequency').unit") == "Hz");
    CHECK(lua.number("run:get('my_sine.amplitude').values[1]") == 30);
    // the controller file is in the run folder, as it ran
    CHECK(read_text(tmp / "run/config/external/1-my_sine.lua") ==
          read_text(GAITLAB_SOURCE_DIR "/examples/controllers/my_sine.lua"));
}
