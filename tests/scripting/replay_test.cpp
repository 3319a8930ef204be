// gaitlab replay (scripting/src/replay.cpp): a run recorded from a script, with changes from
// outside it (a console's parameter change and reset, a controller file edited on disk), is
// rerun from its folder and reproduces the data bit for bit; tampered runs do not.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <thread>

#include "gaitlab/controller.h"
#include "gaitlab/run_data.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/scripting/replay.h"
#include "gaitlab/simulation.h"
#include "temp_dir.h"

using namespace gaitlab;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;
namespace fs = std::filesystem;

namespace {

const char* kController = R"(return gaitlab.controller{
  name = "wave",
  params = { amplitude = { 30, min = 0, max = 60, unit = "deg" } },
  values = { "time" },
  step = function(self, dt)
    for m = 1, self.joints do
      self.time[m] = self.time[m] + dt
      self:set_angle(m, self.amplitude * math.sin(math.pi * self.time[m] + (m - 1) * 2.1))
    end
  end,
}
)";

const char* kScript = R"(local Wave = gaitlab.controller.load("controllers/wave.lua")
local robot = gaitlab.robot.chain{ name = "snake", modules = 5 }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
local ctl = robot:group("pitch"):drive(Wave{ amplitude = 40 })
local sim = gaitlab.simulation{ world = world }
sim:run(0.5)
ctl.amplitude = 35 + math.random(10)   -- the seed decides
sim:run(1.0)
print("done")
)";

// writes the script and its controller into DIR/src, runs it recorded into DIR/run; `outside`
// acts before every tick, as a console would
void record(const TempDir& tmp, const std::function<void(Simulation&)>& outside,
            double reload_interval = 0.2) {
    fs::create_directories(tmp.path / "src/controllers");
    write_text(tmp / "src/controllers/wave.lua", kController);
    write_text(tmp / "src/snake.lua", kScript);
    scripting::LuaHost host;
    scripting::RecordSettings s;
    s.by_default = true;
    s.dir = tmp / "run";
    s.script = tmp / "src/snake.lua";
    host.set_recording(s);
    host.seed(5);
    host.set_reload_interval(reload_interval);
    host.set_print(false);
    // configuration a host adds itself (the XML parts, later) goes into config/ too
    s.files.push_back({"master", "snake.xml", "/somewhere/snake.xml", "<gaitlab/>\n", "", 0, ""});
    host.set_recording(s);
    host.on_simulation([&](Simulation& sim, int) { sim.add_pre_tick(outside); });
    host.run_file(s.script);
    host.finish();
}

}  // namespace

TEST_CASE("changes from a console replay at their ticks, bit for bit", "[replay]") {
    TempDir tmp("replay_console");
    record(tmp, [](Simulation& sim) {
        if (sim.ticks() == 700) sim.controller(0).set_param("amplitude", 20, Origin::console);
        if (sim.ticks() == 1100 && sim.time() > 1) sim.reset(Origin::console);
    });
    const RunData run(tmp / "run");
    const std::vector<Event> events = run.events();
    REQUIRE(events.size() == 3);
    CHECK(events[0].origin == Origin::script);
    CHECK(events[1].origin == Origin::console);
    CHECK(events[2].kind == EventKind::reset);
    CHECK(run.meta().script == "snake.lua");
    CHECK(run.meta().script_seed == 5);
    CHECK(read_text(tmp / "run/config/controllers/wave.lua") == kController);
    CHECK(read_text(tmp / "run/config/snake.lua") == kScript);
    CHECK(read_text(tmp / "run/config/snake.xml") == "<gaitlab/>\n");
    CHECK(run.meta().files[1].role == "master");
    CHECK_THAT(run.log(), Catch::Contains("\ndone\n"));

    const scripting::ReplayResult r = scripting::replay(tmp / "run");
    INFO(r.divergence);
    CHECK(r.into == tmp / "run-replay");
    CHECK(r.divergence.empty());
    CHECK(r.script_error.empty());
    CHECK(r.comparison.difference.empty());
    CHECK(r.ok());
    CHECK(r.applied == 2);
    CHECK(r.comparison.rows == run.rows());
    CHECK(r.comparison.rows > 40);

    // without the console's change the replay goes elsewhere: the check can fail
    fs::copy(tmp / "run", tmp / "edited", fs::copy_options::recursive);
    std::string ev = read_text(tmp / "edited/events.csv");
    const size_t console = ev.find("700,");
    ev.erase(console, ev.find('\n', console) + 1 - console);
    write_text(tmp / "edited/events.csv", ev);
    const scripting::ReplayResult e = scripting::replay(tmp / "edited");
    CHECK_FALSE(e.ok());
    CHECK_THAT(e.comparison.difference, Catch::StartsWith("first difference at t = "));

    // another seed makes the script change something else
    fs::copy(tmp / "run", tmp / "seeded", fs::copy_options::recursive);
    std::string meta = read_text(tmp / "seeded/run.json");
    const size_t seed = meta.find("\"seed\": 5");
    REQUIRE(seed != std::string::npos);
    meta.replace(seed, 9, "\"seed\": 6");
    write_text(tmp / "seeded/run.json", meta);
    const scripting::ReplayResult s = scripting::replay(tmp / "seeded");
    CHECK_FALSE(s.ok());
    CHECK_THAT(s.divergence, Catch::StartsWith("the replay made wave.amplitude = "));
}

TEST_CASE("a controller file changed on disk during the run replays its new version", "[replay]") {
    TempDir tmp("replay_reload");
    std::string file;
    record(
        tmp,
        [&](Simulation& sim) {
            // an editor saves a new version half a second in
            if (sim.ticks() == 500) {
                std::string v2 = kController;
                v2.replace(v2.find("+ (m - 1)"), 9, "- (m - 1)");
                write_text(tmp / "src/controllers/wave.lua", v2);
            }
        },
        0);
    const RunData run(tmp / "run");
    std::vector<Event> reloads;
    for (const Event& e : run.events()) {
        if (e.kind == EventKind::reload) reloads.push_back(e);
    }
    REQUIRE(reloads.size() == 1);
    CHECK(reloads[0].origin == Origin::file);
    CHECK(reloads[0].name == "controllers/wave.lua");
    CHECK(reloads[0].tick == 510);  // the next control tick
    CHECK(reloads[0].detail == "config/reloads/1-wave.v1.lua");
    CHECK_THAT(read_text(tmp / "run/config/reloads/1-wave.v1.lua"), Catch::Contains("- (m - 1)"));

    // the source folder goes back to version 1: the replay must use the run's copies
    write_text(tmp / "src/controllers/wave.lua", kController);
    const scripting::ReplayResult r = scripting::replay(tmp / "run", tmp / "again");
    CHECK(r.divergence.empty());
    CHECK(r.ok());
    CHECK(r.applied == 1);
}

TEST_CASE("a controller file from outside the script's folder replays from the run's copy",
          "[replay]") {
    TempDir tmp("replay_external");
    fs::create_directories(tmp.path / "lib");
    fs::create_directories(tmp.path / "src");
    write_text(tmp / "lib/wave.lua", kController);
    std::string script = kScript;
    script.replace(script.find("\"controllers/wave.lua\""), 22, "\"../lib/wave.lua\"");
    write_text(tmp / "src/snake.lua", script);
    {
        scripting::LuaHost host;
        scripting::RecordSettings s;
        s.dir = tmp / "run";
        s.by_default = true;
        s.script = tmp / "src/snake.lua";
        host.set_recording(s);
        host.set_print(false);
        host.run_file(s.script);
        host.finish();
    }
    CHECK(read_text(tmp / "run/config/external/1-wave.lua") == kController);
    // the original is gone: the replay runs the copy
    fs::remove_all(tmp.path / "lib");
    const scripting::ReplayResult r = scripting::replay(tmp / "run");
    INFO(r.divergence << " / " << r.comparison.difference);
    CHECK(r.script_error.empty());
    CHECK(r.ok());
}

TEST_CASE("a run cut short replays up to its last row", "[replay]") {
    TempDir tmp("replay_short");
    record(tmp, [](Simulation&) {});
    // as a process killed mid-run leaves it: status running, a partly written last line
    std::string meta = read_text(tmp / "run/run.json");
    meta.replace(meta.find("\"finished\""), 10, "\"running\"");
    write_text(tmp / "run/run.json", meta);
    const std::string data = read_text(tmp / "run/data.csv");
    write_text(tmp / "run/data.csv", data.substr(0, data.size() * 2 / 3));
    // while the process that wrote it runs (this one), the run is still being recorded: its
    // replay would be compared with a run that has not ended ("replay differs")
    CHECK_THROWS_WITH(scripting::replay(tmp / "run"),
                      Catch::StartsWith("cannot replay " + tmp / "run" +
                                        ": it is still being recorded (by process "));
    // the process gone (a start time no process of this pid has): replayed to its last row
    const size_t start = meta.find("\"start_time\":");
    REQUIRE(start != std::string::npos);
    meta.insert(meta.find_first_of("0123456789", start), "9");
    write_text(tmp / "run/run.json", meta);
    const RunData run(tmp / "run");
    CHECK(run.truncated());
    const scripting::ReplayResult r = scripting::replay(tmp / "run");
    CHECK(r.ok());
    CHECK(r.stopped_early);
    CHECK(r.comparison.rows == run.rows());
    CHECK(RunData(r.into).rows() == run.rows());

    CHECK_THROWS_WITH(scripting::replay(tmp.str()),
                      Catch::StartsWith(tmp.str() + " is not a run folder: it has no"));
    CHECK_THROWS_WITH(scripting::replay(tmp / "run", tmp / "run"),
                      "cannot replay a run into its own folder");
}

TEST_CASE("a run whose recording failed replays up to its last row", "[replay]") {
    TempDir tmp("replay_full_disk");
    record(tmp, [](Simulation&) {});
    // as a full disk leaves it: "failed" with recording_failed, a partly written last line
    std::string meta = read_text(tmp / "run/run.json");
    meta.replace(meta.find("\"finished\""), 10,
                 "\"failed\", \"message\": \"cannot write data.csv: No space left on device\", "
                 "\"recording_failed\": true");
    write_text(tmp / "run/run.json", meta);
    const std::string data = read_text(tmp / "run/data.csv");
    write_text(tmp / "run/data.csv", data.substr(0, data.size() * 2 / 3));
    const RunData run(tmp / "run");
    REQUIRE(run.meta().recording_failed);
    const scripting::ReplayResult r = scripting::replay(tmp / "run");
    INFO(r.divergence << " / " << r.comparison.difference << " / " << r.failure);
    CHECK(r.ok());
    CHECK(r.stopped_early);
    CHECK(r.run_error.empty());
    CHECK(r.comparison.rows == run.rows());
    CHECK(RunData(r.into).rows() == run.rows());
}

TEST_CASE("a run that failed replays, and is identical when it fails the same way", "[replay]") {
    TempDir tmp("replay_failed");
    fs::create_directories(tmp.path / "src/controllers");
    // a controller that fails at t = 0.4 s, stopping the run (on_controller_error = "stop"),
    // and a script that fails after its run
    write_text(tmp / "src/controllers/breaks.lua", R"(return gaitlab.controller{
  name = "breaks",
  values = { "time" },
  step = function(self, dt)
    for m = 1, self.joints do
      self.time[m] = self.time[m] + dt
      if self.time[m] > 0.4 then error("joint " .. m .. " out of range") end
      self:set_angle(m, 30 * math.sin(math.pi * self.time[m] + m))
    end
  end,
}
)");
    const std::string head = R"(local robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
)";
    write_text(tmp / "src/breaks.lua",
               "local B = gaitlab.controller.load(\"controllers/breaks.lua\")\n" + head +
                   "robot:group(\"pitch\"):drive(B{})\nlocal sim = gaitlab.simulation{ world = "
                   "world }\nsim:run(2)\n");
    write_text(tmp / "src/after.lua",
               head +
                   "local sim = gaitlab.simulation{ world = world }\nsim:run(0.3)\n"
                   "if sim.time > 0.2 then error(\"too far\") end\n");
    const auto run_script = [&](const std::string& name) {
        scripting::LuaHost host;
        scripting::RecordSettings s;
        s.by_default = true;
        s.dir = tmp / name;
        s.script = tmp / ("src/" + name + ".lua");
        host.set_recording(s);
        host.set_print(false);
        std::string error;
        try {
            host.run_file(s.script);
        } catch (const std::exception& e) {
            error = e.what();
        }
        host.finish(error);
        return error;
    };
    for (const std::string name : {"breaks", "after"}) {
        INFO(name);
        const std::string error = run_script(name);
        REQUIRE_FALSE(error.empty());
        const RunData run(tmp / name);
        REQUIRE(run.meta().status == "failed");
        REQUIRE(run.meta().message == error);
        const scripting::ReplayResult r = scripting::replay(tmp / name);
        INFO(r.divergence << " / " << r.comparison.difference << " / " << r.failure << " / "
                          << r.script_error);
        CHECK(r.ok());
        CHECK(r.script_error.empty());
        CHECK(r.run_error == error);
        CHECK(r.failed_at == Approx(name == "breaks" ? 0.4 : 0.3).margin(0.05));
        CHECK(r.comparison.rows == run.rows());
    }
    CHECK_THAT(RunData(tmp / "breaks").meta().message,
               Catch::EndsWith("controllers/breaks.lua:7: joint 1 out of range"));

    // another error, or none, is not the same failure, even with the same data
    std::string meta = read_text(tmp / "after/run.json");
    const size_t at = meta.find("too far");
    meta.replace(at, 7, "far too far");
    write_text(tmp / "after/run.json", meta);
    scripting::ReplayResult o = scripting::replay(tmp / "after", tmp / "other");
    CHECK(o.comparison.identical);
    CHECK_FALSE(o.ok());
    CHECK(o.run_error.empty());
    CHECK_THAT(o.failure, Catch::StartsWith("the run failed at t = 0.3 s with: ") &&
                              Catch::Contains("far too far; the replay at t = 0.3 s with: ") &&
                              Catch::EndsWith(": too far"));
    meta.replace(meta.find("\"failed\""), 8, "\"finished\"");
    write_text(tmp / "after/run.json", meta);
    o = scripting::replay(tmp / "after", tmp / "other");
    CHECK_FALSE(o.ok());
    CHECK_THAT(o.script_error, Catch::EndsWith(": too far"));
    // a run that failed where its replay does not
    write_text(tmp / "src/fine.lua", head +
                                         "local sim = gaitlab.simulation{ world = world }\n"
                                         "sim:run(0.3)\n");
    REQUIRE(run_script("fine").empty());
    meta = read_text(tmp / "fine/run.json");
    meta.replace(meta.find("\"finished\""), 10, "\"failed\", \"message\": \"boom\"");
    write_text(tmp / "fine/run.json", meta);
    o = scripting::replay(tmp / "fine");
    CHECK(o.comparison.identical);
    CHECK_FALSE(o.ok());
    CHECK(o.failure == "the run failed at t = 0.3 s (boom) and the replay did not");
}

TEST_CASE("a run stopped by a signal replays up to the tick where it stopped", "[replay]") {
    TempDir tmp("replay_interrupted");
    record(tmp, [](Simulation&) {});
    // as `gaitlab run` closes it after SIGTERM: status interrupted, last_tick where it stopped
    const RunData full(tmp / "run");
    std::string meta = read_text(tmp / "run/run.json");
    meta.replace(meta.find("\"finished\""), 10, "\"interrupted\", \"message\": \"SIGTERM\"");
    const std::string last = "\"last_tick\": " + std::to_string(full.meta().last_tick);
    meta.replace(meta.find(last), last.size(), "\"last_tick\": 600");
    write_text(tmp / "run/run.json", meta);
    const std::string data = read_text(tmp / "run/data.csv");
    size_t end = 0;
    for (int row = 0; row < 1 + 21; ++row)  // the header and the rows up to tick 600
        end = data.find('\n', end) + 1;
    write_text(tmp / "run/data.csv", data.substr(0, end));
    const scripting::ReplayResult r = scripting::replay(tmp / "run");
    INFO(r.divergence << " / " << r.comparison.difference);
    CHECK(r.ok());
    CHECK(r.stopped_early);
    CHECK(r.comparison.rows == 21);
    CHECK(RunData(r.into).rows() == 21);
}

TEST_CASE("a script that swallows errors stops where the interrupted run stopped", "[replay]") {
    TempDir tmp("replay_swallow");
    fs::create_directories(tmp.path / "src");
    // stopped by a signal while it spun: a replay that only threw ReplayEnd would spin forever
    write_text(tmp / "src/spin.lua",
               R"(local robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
local world = gaitlab.world()
world:add(robot)
local sim = gaitlab.simulation{ world = world }
while true do
  pcall(function() sim:run(0.01) end)
end
)");
    {
        scripting::LuaHost host;
        scripting::RecordSettings s;
        s.by_default = true;
        s.dir = tmp / "run";
        s.script = tmp / "src/spin.lua";
        host.set_recording(s);
        std::thread stopper([&host] {
            std::this_thread::sleep_for(std::chrono::milliseconds(500));
            host.interrupt(SIGTERM);
        });
        CHECK_THROWS_WITH(host.run_file(s.script), Catch::Contains("interrupted (SIGTERM)"));
        stopper.join();
        host.finish("interrupted (SIGTERM)");
    }
    const RunData run(tmp / "run");
    REQUIRE(run.state() == "interrupted by SIGTERM");
    REQUIRE(run.rows() > 1);
    const scripting::ReplayResult r = scripting::replay(tmp / "run");
    INFO(r.divergence << " / " << r.comparison.difference << " / " << r.script_error);
    CHECK(r.ok());
    CHECK(r.stopped_early);
    CHECK(r.script_error.empty());
    CHECK(r.comparison.rows == run.rows());
    // the replay's own folder ends as a replay does, not as interrupted
    CHECK(RunData(r.into).state() == "finished");

    // a caller that interrupts the replay (gaitlab replay on a signal) stops it: interrupted
    std::thread later;
    const scripting::ReplayResult i =
        scripting::replay(tmp / "run", tmp / "stopped", [&later, &tmp](scripting::LuaHost* host) {
            if (host) {
                // as soon as the replay records: well before it reaches the run's end
                later = std::thread([host, &tmp] {
                    const auto deadline =
                        std::chrono::steady_clock::now() + std::chrono::seconds(30);
                    while (!fs::exists(tmp / "stopped/data.csv") &&
                           std::chrono::steady_clock::now() < deadline)
                        std::this_thread::sleep_for(std::chrono::milliseconds(1));
                    host->interrupt(SIGINT);
                });
            } else {
                later.join();  // before the host goes
            }
        });
    CHECK(i.script_error == "interrupted (SIGINT)");
    CHECK(RunData(tmp / "stopped").state() == "interrupted by SIGINT");
    CHECK(RunData(tmp / "stopped").rows() < run.rows());
}

TEST_CASE("a replay reads nothing outside the run's config/", "[replay]") {
    TempDir tmp("replay_outside");
    record(tmp, [](Simulation&) {});
    write_text(tmp / "secret.lua", "error('read from outside')");
    const auto tampered = [&](const std::string& name) {
        fs::copy(tmp / "run", tmp / name, fs::copy_options::recursive);
        return tmp / name;
    };
    // run.json naming a script or controller file outside config/
    std::string dir = tampered("script");
    std::string meta = read_text(dir + "/run.json");
    meta.replace(meta.find("\"script\": \"snake.lua\""), 21, "\"script\": \"../../secret.lua\"");
    write_text(dir + "/run.json", meta);
    CHECK_THROWS_WITH(scripting::replay(dir),
                      Catch::Contains("run.script: a path inside config/ expected, got "
                                      "'../../secret.lua'"));
    dir = tampered("absolute");
    meta = read_text(dir + "/run.json");
    const std::string wave = "\"path\": \"controllers/wave.lua\"";
    meta.replace(meta.find(wave), wave.size(), "\"path\": \"" + tmp / "secret.lua" + "\"");
    write_text(dir + "/run.json", meta);
    CHECK_THROWS_WITH(scripting::replay(dir),
                      Catch::Contains("config[].path: a path inside config/ expected, got '" +
                                      tmp / "secret.lua'"));
    // a link inside config/ that leads out of it
    dir = tampered("link");
    fs::remove(dir + "/config/controllers/wave.lua");
    fs::create_symlink(tmp / "secret.lua", dir + "/config/controllers/wave.lua");
    CHECK_THROWS_WITH(scripting::replay(dir),
                      dir +
                          "/run.json: configuration file 'controllers/wave.lua' leads out of "
                          "config/ (through a link)");
    // a reload event naming a file outside config/
    dir = tampered("event");
    write_text(dir + "/events.csv",
               read_text(dir + "/events.csv") +
                   "300,0.3,file,reload,controllers/wave.lua,1,config/../../../secret.lua\n");
    CHECK_THROWS_WITH(scripting::replay(dir),
                      dir +
                          "/run.json: configuration file '../../../secret.lua' is not inside "
                          "config/");
    // a FIFO as the script: refused, never waited on
    dir = tampered("fifo");
    fs::remove(dir + "/config/snake.lua");
    REQUIRE(::mkfifo((dir + "/config/snake.lua").c_str(), 0600) == 0);
    CHECK_THROWS_WITH(
        scripting::replay(dir),
        "cannot read " + dir + "/config/snake.lua: not a regular file (a FIFO, device or socket)");
}

TEST_CASE("sensors are recorded and their switches from a console replay bit for bit", "[replay]") {
    TempDir tmp("replay_sensors");
    fs::create_directories(tmp.path / "src");
    write_text(tmp / "src/sensing.lua",
               R"(local robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
robot:sensor{ kind = "imu", module = 2 }
robot:sensor{ kind = "contact", module = 4 }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30, phase = 120 })
local sim = gaitlab.simulation{ world = world }
sim:run(1.5)
)");
    scripting::LuaHost host;
    scripting::RecordSettings s;
    s.by_default = true;
    s.dir = tmp / "run";
    s.script = tmp / "src/sensing.lua";
    host.set_recording(s);
    host.set_print(false);
    host.on_simulation([&](Simulation& created, int) {
        created.add_pre_tick([](Simulation& sim) {
            const int imu = sim.find_sensor("snake.imu2");
            if (sim.ticks() == 510) sim.set_sensor_enabled(imu, false, Origin::console);
            if (sim.ticks() == 900) sim.set_sensor_enabled(imu, true, Origin::console);
        });
    });
    host.run_file(s.script);
    host.finish();

    const RunData run(tmp / "run");
    const SeriesData roll = run.get("snake.imu2.roll");
    CHECK(run.find("snake.imu2.roll").kind == SeriesKind::sensor);
    CHECK(run.find("snake.imu2.roll").unit == "deg");
    CHECK(run.find("snake.contact4.force").unit == "N");
    int off = 0, moving = 0;
    for (size_t i = 0; i < roll.time.size(); ++i) {
        const double t = roll.time[i];
        if (t > 0.52 && t < 0.89) {
            CHECK(std::isnan(roll.values[i]));  // switched off: no reading
            ++off;
        } else if (t > 0.91 || t < 0.5) {
            CHECK_FALSE(std::isnan(roll.values[i]));
            moving += roll.values[i] != 0;
        }
    }
    CHECK(off > 10);
    CHECK(moving > 10);
    const std::vector<Event> events = run.events();
    REQUIRE(events.size() == 2);
    CHECK(events[0].kind == EventKind::sensor);
    CHECK(events[0].name == "snake.imu2");
    CHECK(events[0].value == 0);
    CHECK(events[0].tick == 510);
    CHECK(events[0].origin == Origin::console);
    CHECK(events[1].value == 1);

    const scripting::ReplayResult r = scripting::replay(tmp / "run");
    INFO(r.divergence);
    CHECK(r.ok());
    CHECK(r.applied == 2);
    CHECK(r.comparison.rows == run.rows());
}
