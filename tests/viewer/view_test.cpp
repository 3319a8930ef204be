// The view between a Lua host and its pages: sim:run plays at the pace of the simulation's
// player, the pages' commands (pause, step, speed, parameters, reset) act at tick boundaries,
// changes are recorded as events from the viewer, and the run replays bit for bit.
#include "gaitlab/viewer/view.h"

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include <httplib.h>
#include <catch2/catch.hpp>

#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/scripting/replay.h"
#include "temp_dir.h"

using namespace gaitlab;
using namespace gaitlab::viewer;
using Clock = std::chrono::steady_clock;

namespace {

const char* kSnake = R"(
local robot = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-pitch" }
local world = gaitlab.world{}
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 1, phase = 120 })
sim = gaitlab.simulation{ world = world }
)";

double seconds_since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

// a page's command; false if it was not accepted (called from the page's thread: no REQUIRE)
bool post(int port, const std::string& body) {
    httplib::Client c("127.0.0.1", port);
    auto r = c.Post("/api/command", body, "application/json");
    return r && r->status == 200;
}

// a page's thread: joined however the test leaves
struct Page {
    std::thread thread;
    std::atomic<bool> ok{true};
    ~Page() {
        if (thread.joinable()) thread.join();
    }
};

// waits until the view has published `n` frames (the run is under way), at most 20 s
void wait_frames(View& view, std::uint64_t n) {
    const auto end = Clock::now() + std::chrono::seconds(20);
    while (view.server().stats().frames < n && Clock::now() < end)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

ViewOptions no_wait() {
    ViewOptions o;
    o.wait_for_page = false;
    return o;
}

}  // namespace

TEST_CASE("under a view sim:run plays at real time and a page's speed makes it as fast as it can") {
    scripting::LuaHost host;
    View view(host, {}, no_wait());
    host.run_string(kSnake, "snake");
    auto start = Clock::now();
    host.run_string("sim:run(0.4) assert(sim.ticks == 400)", "run");
    const double wall = seconds_since(start);
    CHECK(wall >= 0.38);
    CHECK(wall < 2);
    // a page asks for as fast as possible while 60 s run
    const int port = view.server().port();
    Page page;
    page.thread = std::thread([&page, port] {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        page.ok = post(port, R"({"command":"speed","value":"max"})");
    });
    start = Clock::now();
    host.run_string("sim:run(60) assert(sim.ticks == 60400)", "run");
    page.thread.join();
    CHECK(page.ok);
    CHECK(seconds_since(start) < 30);
    // without a view, runs are not paced again: 4 simulated seconds take well under 4 s (the
    // bound leaves room for a loaded machine; unpaced, this takes about a tenth of a second)
    scripting::LuaHost plain;
    plain.run_string(kSnake, "snake");
    start = Clock::now();
    plain.run_string("sim:run(4)", "run");
    CHECK(seconds_since(start) < 2);
}

TEST_CASE("a page pauses and steps a run and changes a parameter and the run replays bit for bit") {
    test::TempDir dir("view_test");
    const std::string script = dir / "snake.lua";
    test::write_text(script, std::string(kSnake) + R"(
sim:run(0.6)
assert(sim.ticks == 600, "the run ran " .. sim.ticks .. " ticks")
)");
    const std::string run = dir / "run";
    {
        scripting::LuaHost host;
        scripting::RecordSettings rec;
        rec.by_default = true;
        rec.dir = run;
        rec.script = script;
        rec.command = "gaitlab run snake.lua --view";
        host.set_recording(rec);
        View view(host, {}, no_wait());
        const int port = view.server().port();
        Page page;
        page.thread = std::thread([&] {
            wait_frames(view, 6);  // about 0.1 s into the run
            bool ok = post(port, R"({"command":"pause","simulation":1})");
            std::this_thread::sleep_for(std::chrono::milliseconds(400));
            ok = ok && post(port, R"({"command":"param","controller":"sine","name":"amplitude",)"
                                  R"("value":20})");
            ok = ok && post(port, R"({"command":"step","ticks":30})");
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            page.ok = ok && post(port, R"({"command":"play"})");
        });
        const auto start = Clock::now();
        host.run_file(script);
        const double wall = seconds_since(start);
        page.thread.join();
        CHECK(page.ok);
        // 0.6 s of simulated time at real time, plus about half a second held
        CHECK(wall >= 0.6 + 0.4);
        host.finish();
    }
    const std::string events = test::read_text(run + "/events.csv");
    INFO(events);
    CHECK(events.find(",viewer,param,sine.amplitude,20,") != std::string::npos);
    const scripting::ReplayResult r = scripting::replay(run);
    INFO(r.divergence << r.comparison.difference << r.script_error);
    CHECK(r.ok());
    CHECK(r.applied == 1);
}

TEST_CASE("a page resets a run: the run still does its ticks and replays bit for bit") {
    test::TempDir dir("view_test");
    const std::string script = dir / "snake.lua";
    test::write_text(script, std::string(kSnake) + R"(
sim:run(0.5)
-- a reset about 0.2 s in: the run's 500 ticks end near 0.3 s
assert(sim.time < 0.49, "no reset happened: t = " .. sim.time)
)");
    const std::string run = dir / "run";
    {
        scripting::LuaHost host;
        scripting::RecordSettings rec;
        rec.by_default = true;
        rec.dir = run;
        rec.script = script;
        rec.command = "gaitlab run snake.lua --view";
        host.set_recording(rec);
        View view(host, {}, no_wait());
        const int port = view.server().port();
        Page page;
        page.thread = std::thread([&] {
            wait_frames(view, 12);  // about 0.2 s into the run
            page.ok = post(port, R"({"command":"reset"})");
        });
        host.run_file(script);
        page.thread.join();
        CHECK(page.ok);
        host.finish();
    }
    CHECK(test::read_text(run + "/events.csv").find(",viewer,reset,") != std::string::npos);
    const scripting::ReplayResult r = scripting::replay(run);
    INFO(r.divergence << r.comparison.difference << r.script_error);
    CHECK(r.ok());
}

TEST_CASE("the scene names every body and object and parameter") {
    scripting::LuaHost host;
    View view(host, {}, no_wait());
    host.run_string(R"(
local robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
local world = gaitlab.world{}
world:box{ size = { 0.1, 0.1, 0.1 }, position = { 1, 0, 0.05 }, mass = 0.2 }
world:ramp{ slope = 15, length = 0.3, width = 0.3, position = { -1, 0, 0 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{})
sim = gaitlab.simulation{ world = world }
)",
                    "scene");
    httplib::Client c("127.0.0.1", view.server().port());
    auto r = c.Get("/api/scene");
    REQUIRE(r);
    const std::string s = r->body;
    INFO(s);
    CHECK(s.find("\"robots\":[{\"bodies\":4,\"first_body\":0,\"name\":\"snake\"}]") !=
          std::string::npos);
    CHECK(s.find("\"name\":\"box 1\"") != std::string::npos);
    CHECK(s.find("\"dynamic\":0") != std::string::npos);
    CHECK(s.find("\"kind\":\"mesh\"") != std::string::npos);
    CHECK(s.find("{\"default\":40.0,\"max\":90.0,\"min\":0.0,\"name\":\"amplitude\",\"unit\":"
                 "\"deg\"}") != std::string::npos);
    CHECK(view.server().stats().frames >= 1);
}

TEST_CASE("a page's delay adds wall time between the physics steps of a run") {
    scripting::LuaHost host;
    View view(host, {}, no_wait());
    host.run_string(kSnake, "snake");
    const int port = view.server().port();
    // 2 ms a step: 100 ticks take at least 0.2 s of wall time instead of 0.1 s
    REQUIRE(post(port, R"({"command": "delay", "value": 0.002})"));
    auto start = Clock::now();
    host.run_string("sim:run(0.1) assert(sim.ticks == 100)", "run");
    CHECK(seconds_since(start) >= 0.19);
    // back to none: the next 100 ticks are at real time again
    REQUIRE(post(port, R"({"command": "delay", "value": 0})"));
    start = Clock::now();
    host.run_string("sim:run(0.1) assert(sim.ticks == 200)", "run");
    CHECK(seconds_since(start) < 0.19);
}

TEST_CASE("a page chooses which of a script's simulations it shows and addresses") {
    scripting::LuaHost host;
    View view(host, {}, no_wait());
    // simulation 1, its clone 2, and 3 with another robot
    host.run_string(R"(
local robot = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-pitch" }
local world = gaitlab.world{}
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 1, phase = 120 })
sim = gaitlab.simulation{ world = world }
sim:step(10)
copy = sim:clone()
local worm = gaitlab.robot.chain{ name = "worm", modules = 2 }
local other = gaitlab.world{}
other:add(worm)
worm:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 10 })
third = gaitlab.simulation{ world = other }
)",
                    "three");
    httplib::Client c("127.0.0.1", view.server().port());
    auto scene_of = [&c] {
        auto r = c.Get("/api/scene");
        REQUIRE(r);
        return r->body;
    };
    auto r = c.Get("/api/simulations");
    REQUIRE(r);
    INFO(r->body);
    CHECK(r->body.find(R"({"controllers":["sine"],"robots":["snake"],"shown":false,)"
                       R"("simulation":1})") != std::string::npos);
    CHECK(r->body.find(R"("robots":["snake"],"shown":false,"simulation":2})") != std::string::npos);
    CHECK(r->body.find(R"("robots":["worm"],"shown":true,"simulation":3})") != std::string::npos);
    CHECK(r->body.find(R"("chosen":false)") != std::string::npos);
    CHECK(scene_of().find("\"simulation\":3") != std::string::npos);

    // the page chooses the clone: the scene, the frames and commands without a number go to it
    REQUIRE(post(view.server().port(), R"({"command":"show","simulation":2})"));
    view.poll();
    const std::string scene = scene_of();
    CHECK(scene.find("\"simulation\":2") != std::string::npos);
    CHECK(scene.find("\"name\":\"snake\"") != std::string::npos);
    r = c.Get("/api/simulations");
    REQUIRE(r);
    CHECK(r->body.find(R"("shown":true,"simulation":2})") != std::string::npos);
    CHECK(r->body.find(R"("chosen":true)") != std::string::npos);
    REQUIRE(post(view.server().port(),
                 R"({"command":"param","controller":"sine","name":"amplitude","value":25})"));
    view.poll();
    host.run_string(R"(
assert(copy:robot("snake"):controllers()[1].amplitude == 25, "the clone's amplitude")
assert(sim:robot("snake"):controllers()[1].amplitude == 40, "the original's amplitude")
)",
                    "check");
    // the live series are the clone's
    r = c.Get("/api/live/series");
    REQUIRE(r);
    CHECK(r->body.find("\"simulation\":2") != std::string::npos);

    // a simulation made now does not take the page's choice away; it is listed
    host.run_string("fourth = gaitlab.simulation{ world = gaitlab.world{} }", "fourth");
    CHECK(scene_of().find("\"simulation\":2") != std::string::npos);
    r = c.Get("/api/simulations");
    REQUIRE(r);
    CHECK(r->body.find(R"("simulation":4})") != std::string::npos);

    // one that is not there: refused with the list, nothing changes
    httplib::Client p("127.0.0.1", view.server().port());
    auto bad = p.Post("/api/command", R"({"command":"show","simulation":9})", "application/json");
    REQUIRE(bad);
    CHECK(bad->status == 400);
    CHECK(bad->body.find("there is no simulation 9 (there are 1, 2, 3, 4)") != std::string::npos);
    view.poll();
    CHECK(scene_of().find("\"simulation\":2") != std::string::npos);
}
