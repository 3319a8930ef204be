// The console's core (scripting/src/console.cpp), fed lines as a person would type them, and
// gaitlab.pretty (stdlib/pretty.lua), which prints its results.
#include <catch2/catch.hpp>

#include <lua.hpp>

#include <chrono>
#include <csignal>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "gaitlab/scripting/console.h"
#include "gaitlab/scripting/lua_host.h"
#include "temp_dir.h"

using gaitlab::scripting::Console;
using gaitlab::scripting::LuaHost;
using gaitlab::test::TempDir;
using Status = Console::Status;

namespace {

// a console whose output is kept, over a host of its own
struct Session {
    LuaHost host;
    Console console{host};
    std::string out, err;

    Session() {
        console.set_writers([this](const std::string& t) { out += t; },
                            [this](const std::string& t) { err += t; });
        host.set_output([this](const std::string& t) { out += t; });
    }
    // feeds the lines of `text`; returns the status of the last one
    Status type(const std::string& text) {
        Status s = Status::ran;
        std::istringstream in(text);
        for (std::string line; std::getline(in, line);)
            s = console.feed(line);
        return s;
    }
    // the output of one line, forgotten afterwards
    std::string result(const std::string& line) {
        out.clear();
        err.clear();
        console.feed(line);
        std::string r = out;
        out.clear();
        return r;
    }
    int top() { return lua_gettop(host.state()); }
};

const char* kSnake =
    "world = gaitlab.world{}\n"
    "robot = gaitlab.robot.chain{ name = 'snake', modules = 4 }\n"
    "world:add(robot)\n"
    "ctl = robot:group('pitch'):drive(gaitlab.controllers.sine{ amplitude = 30 })\n"
    "sim = gaitlab.simulation{ world = world }\n";

}  // namespace

TEST_CASE("bare expressions and =expr print their values, tab-separated", "[console]") {
    Session s;
    CHECK(s.result("1 + 1") == "2\n");
    CHECK(s.result("=2^10") == "1024.0\n");
    CHECK(s.result("= 1, nil, 'x'") == "1\tnil\tx\n");
    CHECK(s.result("x = 5") == "");
    CHECK(s.result("x") == "5\n");
    CHECK(s.result("return x * 2, x") == "10\t5\n");
    // statements print nothing, and print() works
    CHECK(s.result("print('a', 1, true)") == "a\t1\ttrue\n");
    CHECK(s.result("math.sin").rfind("function: ", 0) == 0);
    CHECK(s.top() == 0);
    CHECK(s.err.empty());
}

TEST_CASE("an incomplete chunk continues on the next lines", "[console]") {
    Session s;
    CHECK(std::string(s.console.prompt()) == "> ");
    CHECK(s.console.feed("function f(a)") == Status::more);
    CHECK(std::string(s.console.prompt()) == ">> ");
    CHECK(s.console.pending());
    CHECK(s.console.feed("  return a * 3") == Status::more);
    CHECK(s.console.feed("end") == Status::ran);
    CHECK(s.console.last_chunk() == "function f(a)\n  return a * 3\nend");
    CHECK(std::string(s.console.prompt()) == "> ");
    CHECK(s.result("f(4)") == "12\n");
    // an unfinished string and table also continue; a discarded chunk is forgotten
    CHECK(s.console.feed("t = {") == Status::more);
    s.console.discard();
    CHECK_FALSE(s.console.pending());
    CHECK(s.result("=t") == "nil\n");
    CHECK(s.type("t = {\n1, 2,\n3 }") == Status::ran);
    CHECK(s.result("=#t") == "3\n");
    CHECK(s.top() == 0);
}

TEST_CASE("errors print with a traceback and the session goes on", "[console]") {
    Session s;
    CHECK(s.console.feed("error('boom')") == Status::ran);
    CHECK(s.err.rfind("console:1: boom\nstack traceback:\n", 0) == 0);
    CHECK(s.err.find("in main chunk") != std::string::npos);
    s.err.clear();
    CHECK(s.console.feed("x = = 1") == Status::rejected);
    CHECK(s.err == "console:1: unexpected symbol near '='\n");
    s.err.clear();
    CHECK(s.console.feed("error({})") == Status::ran);
    CHECK(s.err.rfind("console:1: (error object is a table value)", 0) == 0);
    s.err.clear();
    // a __tostring that fails: the value still prints, with why
    s.type("bad = setmetatable({}, { __tostring = function() error('no') end })");
    CHECK(s.result("bad") == "<table: __tostring failed: console:1: no>\n");
    // a printer that fails: what cannot be printed is said
    s.type("gaitlab.pretty = function() error('no printer') end");
    CHECK(s.result("1") == "");
    CHECK(s.err.rfind("cannot print the result: console:1: no printer", 0) == 0);
    CHECK(s.result("print(1 + 2)") == "3\n");
    CHECK(s.top() == 0);
}

TEST_CASE("errors show control characters as hex escapes, results and prints as they are",
          "[console]") {
    Session s;
    // a gaitlab error quoting a typed string, a Lua error of the session's own
    s.console.feed("gaitlab.robot.chain{ modules = 2, module = 'y1\\27[31m\\0' }");
    CHECK_THAT(s.err, Catch::StartsWith("console:1: bad argument #1 to 'chain' (field 'module': "
                                        "unknown module type 'y1\\x1b[31m\\x00'"));
    s.err.clear();
    s.console.feed("error('\\27]0;title\\7 \\194\\155 \\255 \\206\\188', 0)");
    CHECK_THAT(s.err, Catch::StartsWith("\\x1b]0;title\\x07 \\xc2\\x9b \\xff \xce\xbc\nstack "
                                        "traceback:\n"));
    s.err.clear();
    // the session's own values and prints are its output
    CHECK(s.result("='\\27[1m'") == "\x1b[1m\n");
    CHECK(s.result("print('\\27[1m')") == "\x1b[1m\n");
    CHECK(s.err.empty());
}

TEST_CASE("bad input never ends the session", "[console]") {
    Session s;
    // garbage, binary, zeros, a huge line, a binary chunk, unbalanced brackets
    const std::string lines[] = {")))(((",
                                 std::string("x\0y", 3),
                                 std::string("\x1bLua\x54\x00\x19\x93\x0d", 9),
                                 "\xff\xfe\xfd",
                                 std::string(1 << 20, 'a') + " = 1",
                                 "=" + std::string(100000, '('),
                                 "end end end",
                                 "--[[ unfinished comment"};
    for (const std::string& l : lines) {
        s.console.feed(l);
        s.console.discard();
        CHECK(s.top() == 0);
    }
    CHECK(s.result("=" + std::string(1 << 20, 'a')) == "1\n");
    // a string with a zero prints whole
    CHECK(s.result("='a\\0b'") == std::string("a\0b\n", 4));
    // an endless loop is stopped by an interrupt from another thread (Ctrl-C's handler)
    std::thread ctrl_c([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        s.host.interrupt(SIGINT);
    });
    s.err.clear();
    CHECK(s.console.feed("while true do end") == Status::ran);
    ctrl_c.join();
    CHECK(s.err.rfind("interrupted (SIGINT)", 0) != std::string::npos);
    CHECK(s.host.interrupted() == 0);
    CHECK(s.result("2 * 21") == "42\n");
    CHECK(s.top() == 0);
}

TEST_CASE("a line that errors inside a controller keeps the simulation", "[console]") {
    Session s;
    s.type(kSnake);
    s.type(
        "Bad = gaitlab.controller{ name = 'bad', params = { gain = { 1, min = 0, max = 2 } },\n"
        "  step = function(self) if self.gain > 1.5 then error('too much gain') end end }\n"
        "bad = Bad{}\n"
        "robot:group('yaw')");
    s.err.clear();
    s.type(
        "sim2w = gaitlab.world{}\n"
        "r2 = gaitlab.robot.chain{ name = 'r2', modules = 2 }\n"
        "sim2w:add(r2)\n"
        "b = r2:group('all'):drive(Bad{})\n"
        "sim2 = gaitlab.simulation{ world = sim2w, on_controller_error = 'stop' }\n"
        "b.gain = 1.8\n"
        "sim2:run(0.1)");
    CHECK(s.err.find("too much gain") != std::string::npos);
    // the first simulation is untouched and runs on
    CHECK(s.result("sim:run(0.1)") == "");
    CHECK(s.result("=sim.time > 0.09") == "true\n");
    CHECK(s.result("=ctl.failed") == "false\n");
}

TEST_CASE("Ctrl-C during sim:run returns with the simulation intact", "[console]") {
    Session s;
    s.type(kSnake);
    std::thread ctrl_c([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        s.host.interrupt(SIGINT);
    });
    CHECK(s.console.feed("sim:run(1e6)") == Status::ran);
    ctrl_c.join();
    CHECK(s.err.find("interrupted (SIGINT)") != std::string::npos);
    s.out.clear();
    s.type("t0 = sim.time");
    CHECK(s.result("=t0 > 0 and t0 < 1e6") == "true\n");
    s.type("sim:run(0.5)");
    CHECK(s.result("=math.abs(sim.time - t0 - 0.5) < 1e-9") == "true\n");
    CHECK(s.result("=ctl.failed") == "false\n");
}

TEST_CASE("changes typed at the console are recorded with origin console", "[console]") {
    TempDir dir("console_origin");
    const std::string run = dir.file("run");
    {
        Session s;
        s.type(kSnake);
        s.type("sim:record('" + run + "')");
        s.type("sim:run(0.1)");
        s.type("ctl.phase = 90");
        // code that names its origin keeps it; the host's origin is restored after a line
        s.type("ctl:set('amplitude', 20, 'viewer')");
        s.type("sim:run(0.1)");
        s.type("sim:reset()");
        CHECK(s.host.origin() == gaitlab::Origin::script);
        s.host.run_string("ctl.phase = 45", "=script");
        s.host.finish();
        CHECK(s.err.empty());
    }
    std::ifstream in(run + "/events.csv");
    std::stringstream text;
    text << in.rdbuf();
    CHECK(text.str() ==
          "tick,time,origin,kind,name,value,detail\n"
          "100,0.1,console,param,sine.phase,90,\n"
          "100,0.1,viewer,param,sine.amplitude,20,\n"
          "200,0.2,console,reset,,0,\n"
          "0,0,script,param,sine.phase,45,\n");
}

TEST_CASE("pretty printing of tables", "[console][pretty]") {
    Session s;
    CHECK(s.result("{}") == "{}\n");
    CHECK(s.result("{1, 2, 3}") == "{ 1, 2, 3 }\n");
    CHECK(s.result("{b = 1, a = 'x', [3.5] = true, 10}") ==
          "{ 10, [3.5] = true, a = \"x\", b = 1 }\n");
    CHECK(s.result("{['not a name'] = 1, ['end'] = 2}") ==
          "{ [\"end\"] = 2, [\"not a name\"] = 1 }\n");
    CHECK(s.result("{'a\\nb'}") == "{ \"a\\nb\" }\n");
    // cycles are marked, nesting is limited
    s.type("t = {name = 't'}; t.self = t");
    CHECK(s.result("t") == "{ name = \"t\", self = <cycle> }\n");
    CHECK(s.result("{{{{{{1}}}}}}") == "{ { { { {...} } } } }\n");
    // long tables are cut, on several lines
    const std::string big =
        s.result("(function() local t = {} for i = 1, 1e6 do t[i] = i end return t end)()");
    CHECK(big.find("... (999960 more)") != std::string::npos);
    CHECK(big.size() < 2000);
    // a table shared 2^30 times over prints in bounded time and size
    const auto start = std::chrono::steady_clock::now();
    const std::string shared =
        s.result("(function() local t = {} for i = 1, 30 do t = {t, t, t} end return t end)()");
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(2));
    CHECK(shared.size() < 20000);
    // a huge hash table: cut, sorted among the keys looked at
    const std::string hash =
        s.result("(function() local t = {} for i = 1, 2e5 do t['k' .. i] = i end return t end)()");
    CHECK(hash.find("... (") != std::string::npos);
    CHECK(hash.size() < 4000);
    // vectors use their __tostring; bad options are errors in Lua's words
    CHECK(s.result("gaitlab.vec3(1, 2, 3)") == "(1, 2, 3)\n");
    CHECK(s.result("gaitlab.pretty({1, {2}}, { depth = 1 })") == "{ 1, {...} }\n");
    // a __tostring that fails says why; a huge one is cut
    CHECK(s.result("setmetatable({}, { __tostring = function() error('boom', 0) end })") ==
          "<table: __tostring failed: boom>\n");
    const std::string huge =
        s.result("setmetatable({}, { __tostring = function() return ('x'):rep(1e6) end })");
    CHECK(huge == std::string(4096, 'x') + "... (995904 more bytes)\n");
    s.console.feed("gaitlab.pretty(1, { depth = -1 })");
    CHECK(s.err.find("bad argument #2 to 'pretty' (field 'depth': a whole number >= 0 expected)") !=
          std::string::npos);
}

TEST_CASE("pretty printing of gaitlab objects", "[console][pretty]") {
    Session s;
    s.type("lone = gaitlab.robot.chain{ name = 'lone', modules = 2, connection = 'pitch-yaw' }");
    CHECK(s.result("lone") ==
          "robot 'lone': 2 y1 modules, pitch-yaw\n"
          "  not in a simulation yet (no pose)\n"
          "  joint  name          role      angle   target   range\n"
          "      1  joint1        pitch         -        -   -90° .. 90°\n"
          "      2  joint2        yaw           -        -   -90° .. 90°\n");
    s.type(kSnake);
    s.type("sim:run(0.5)");
    const std::string robot = s.result("robot");
    CHECK(robot.rfind("robot 'snake': 4 y1 modules, pitch-pitch\n  position  x 0.1", 0) == 0);
    CHECK(robot.find(" m (centre of mass)\n") != std::string::npos);
    CHECK(robot.find("\n      4  joint4        pitch   ") != std::string::npos);
    CHECK(robot.find("°   -90° .. 90°\n") != std::string::npos);
    CHECK(s.result("ctl") ==
          "controller 'sine'\n"
          "  amplitude = 30         deg   range 0 .. 90, default 40\n"
          "  frequency = 0.5        Hz    range 0 .. 5, default 0.5\n"
          "  offset    = 0          deg   range -90 .. 90, default 0\n"
          "  phase     = 120        deg   range -180 .. 180, default 120\n"
          "  phase0    = 0          deg   range -180 .. 180, default 0\n");
    CHECK(s.result("sim") ==
          "simulation: t = 0.500 s (500 ticks of 0.001 s, controllers every 30)\n"
          "  recording off\n");
    CHECK(s.result("robot:group('all')") == "group of 4 joints: 1, 2, 3, 4\n");
    CHECK(s.result("world") == "gaitlab.World (1 robot, 0 boxes)\n");
    // a sensor's tostring says it all, its state once
    CHECK(s.result("imu = robot:sensor{ kind = 'imu', module = 2 } return imu") ==
          "gaitlab.Sensor 'imu2' (imu on module 2 (head half), on)\n");
    s.type("imu:off()");
    CHECK(s.result("imu") == "gaitlab.Sensor 'imu2' (imu on module 2 (head half), off)\n");
    // inside a table, objects are one word
    CHECK(s.result("{ctl}") == "{ gaitlab.Controller 'sine' }\n");
}

TEST_CASE("completion of globals, fields and methods", "[console][completion]") {
    Session s;
    s.type(kSnake);
    using V = std::vector<std::string>;
    CHECK(s.console.complete("robot:gr") == V{"robot:group("});
    CHECK(s.console.complete("gaitlab.sim") == V{"gaitlab.simulation"});
    CHECK(s.console.complete("x = gaitlab.robot.ch") == V{"gaitlab.robot.chain("});
    CHECK(s.console.complete("sim:re") == V{"sim:record(", "sim:reset("});
    CHECK(s.console.complete("ctl.amp") == V{"ctl.amplitude"});
    CHECK(s.console.complete("ctl:par") == V{"ctl:params("});
    CHECK(s.console.complete("gaitlab.vec3(1,2,3):no") == V{});  // not a name path
    CHECK(s.console.complete("whi") == V{"while"});
    CHECK(s.console.complete("rob") == V{"robot"});
    CHECK(s.console.complete("print(str") == V{"string"});
    CHECK(s.console.complete("string.fo") == V{"string.format("});
    // tables with metatables: __index tables are followed, no metamethod runs
    s.type(
        "calls = 0\n"
        "base = { hello = function() end }\n"
        "obj = setmetatable({ own = 1 }, { __index = base })\n"
        "trap = setmetatable({}, { __index = function() calls = calls + 1 end })");
    CHECK(s.console.complete("obj.") == V{"obj.hello(", "obj.own"});
    CHECK(s.console.complete("obj:he") == V{"obj:hello("});
    CHECK(s.console.complete("trap.x.y") == V{});
    CHECK(s.result("calls") == "0\n");
    // nothing for numbers, unknown names, a method in the middle, garbage
    CHECK(s.console.complete("3.1") == V{});
    CHECK(s.console.complete("nothing.here") == V{});
    CHECK(s.console.complete("robot:group.x") == V{});
    CHECK(s.console.complete(std::string("\0\xff", 2)) == V{});
    CHECK(s.console.complete("") == V{});
    CHECK(s.top() == 0);
}
