// `gaitlab make robot|world|actuation|sim` (cli/make.cpp, through cli/parts.cpp): each kind of
// file, read back by the engine's readers; a made simulation that runs; bad options, each with
// one clear line and no file written.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "gaitlab/xml.h"
#include "run_gaitlab.h"

using gaitlab::test::Output;
using gaitlab::test::run_gaitlab;
using gaitlab::test::TempDir;

namespace {

Output make(std::vector<std::string> args, const TempDir& dir) {
    args.insert(args.begin(), "make");
    return run_gaitlab(args, dir.str());
}

// a failure: status 1 or 2, nothing on stdout, exactly `line` on stderr, no file `out`
void check_failure(const Output& r, const std::string& line) {
    INFO("stdout: " << r.out);
    CHECK((r.status == 1 || r.status == 2));
    CHECK(r.out.empty());
    CHECK(r.err == line + "\n");
}

double param(const gaitlab::ControllerRef& c, const std::string& name) {
    for (const auto& [n, v] : c.params)
        if (n == name) return v;
    return -1e9;
}

}  // namespace

TEST_CASE("make builds each part, and the parts run together", "[cli][make]") {
    TempDir dir("make_parts");
    Output r = make({"robot", "--modules", "8", "--connection", "pitch-yaw", "--sensor", "imu",
                     "--sensor", "contact:2", "-o", "snake.xml"},
                    dir);
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());
    CHECK(r.out == "wrote snake.xml (robot 'robot': 8 modules, pitch-yaw)\n");
    const gaitlab::RobotSpec robot = gaitlab::read_robot(dir / "snake.xml");
    CHECK(robot.name == "robot");
    CHECK(robot.joints.size() == 8);
    REQUIRE(robot.sensors.size() == 2);
    CHECK(robot.sensors[0].name == "imu8");
    CHECK(robot.sensors[1].name == "contact2");

    r = make({"actuation", "--robot", "snake.xml", "--group", "pitch=sine:amplitude=40:phase=-120",
              "--group", "yaw=offset", "-o", "parts/act.xml"},
             dir);
    REQUIRE(r.status == 0);
    CHECK(r.out == "wrote parts/act.xml (2 groups)\n");
    const gaitlab::ActuationSpec act = gaitlab::read_actuation(dir / "parts/act.xml");
    REQUIRE(act.groups.size() == 2);
    CHECK(act.groups[0].role == "pitch");
    CHECK(act.groups[0].controller.name == "sine");
    CHECK(param(act.groups[0].controller, "amplitude") == 40);
    CHECK(param(act.groups[0].controller, "phase") == -120);
    CHECK(act.groups[1].role == "yaw");
    CHECK(act.groups[1].controller.name == "offset");

    r = make(
        {"world", "--preset", "ramp", "--friction", "0.6", "--param", "slope=12", "-o", "ramp.xml"},
        dir);
    REQUIRE(r.status == 0);
    const gaitlab::EnvironmentSpec env = gaitlab::read_environment(dir / "ramp.xml");
    CHECK(env.world.floor.friction == 0.6);
    // the ramp's start: the robot on the slope, for the robot named "robot" by default
    REQUIRE(env.placements.size() == 1);
    CHECK(env.placements[0].robot == "robot");
    CHECK(env.placements[0].pose.position.x == Approx(0.1));

    r = make({"sim", "--robot", "snake.xml", "--actuation", "parts/act.xml", "--world", "ramp.xml",
              "--duration", "2", "--control-every", "20", "-o", "sim.xml"},
             dir);
    REQUIRE(r.status == 0);
    CHECK(r.out == "wrote sim.xml (run it: gaitlab run sim.xml)\n");
    const gaitlab::SimulationFile sim = gaitlab::read_simulation(dir / "sim.xml");
    CHECK(sim.name == "sim");
    CHECK(sim.duration == 2);
    CHECK(sim.options.control_every == 20);
    CHECK(sim.environment == "ramp.xml");
    REQUIRE(sim.robots.size() == 1);
    CHECK(sim.robots[0].actuation == "parts/act.xml");

    const Output run = run_gaitlab({"run", "--no-record", "sim.xml"}, dir.str());
    CHECK(run.status == 0);
    CHECK_THAT(run.out,
               Catch::Matches(R"(robot: moved 0\.[0-9]+ m \(x -?[0-9.]+, y -?[0-9.]+\) in 2 s\n)"));
}

TEST_CASE("one robot file serves worlds made for its name and a flat world for any",
          "[cli][make]") {
    TempDir dir("make_reuse");
    REQUIRE(make({"robot", "--name", "worm", "--modules", "6", "-o", "worm.xml"}, dir).status == 0);
    REQUIRE(
        make({"actuation", "--robot", "worm.xml", "--group", "all=sine:phase=-120", "-o", "a.xml"},
             dir)
            .status == 0);
    // a flat world has its start at the origin: it names no robot
    REQUIRE(make({"world", "-o", "flat.xml"}, dir).status == 0);
    CHECK(gaitlab::read_environment(dir / "flat.xml").placements.empty());
    REQUIRE(make({"world", "--preset", "stairs", "--robot", "worm.xml", "-o", "stairs.xml"}, dir)
                .status == 0);
    CHECK(gaitlab::read_environment(dir / "stairs.xml").placements.at(0).robot == "worm");
    for (const char* world : {"flat.xml", "stairs.xml"}) {
        INFO(world);
        REQUIRE(make({"sim", "--robot", "worm.xml", "--actuation", "a.xml", "--world", world,
                      "--duration", "1", "--no-record", "-o", "s.xml"},
                     dir)
                    .status == 0);
        CHECK(gaitlab::read_simulation(dir / "s.xml").record.enabled == false);
        const Output run = run_gaitlab({"run", "s.xml"}, dir.str());
        CHECK(run.status == 0);
        CHECK_THAT(run.out, Catch::StartsWith("worm: moved "));
    }
    // a ramp made for the default name does not fit a robot called worm: said before writing
    REQUIRE(make({"world", "--preset", "ramp", "-o", "ramp.xml"}, dir).status == 0);
    const Output bad =
        make({"sim", "--robot", "worm.xml", "--world", "ramp.xml", "-o", "r.xml"}, dir);
    check_failure(bad, "gaitlab: make sim: " + dir.str() +
                           "/ramp.xml:7: robot 'robot' is placed but the simulation has no robot "
                           "of that name");
    CHECK(!std::filesystem::exists(dir / "r.xml"));
    // nothing left beside the files asked for
    for (const auto& e : std::filesystem::directory_iterator(dir.path))
        CHECK(e.path().filename().string()[0] != '.');
}

TEST_CASE("make rejects bad options with one clear line and writes nothing", "[cli][make]") {
    TempDir dir("make_bad");
    REQUIRE(make({"robot", "-o", "r.xml"}, dir).status == 0);
    check_failure(make({"world", "--preset", "moon", "-o", "w.xml"}, dir),
                  "gaitlab: make world: unknown world 'moon' (worlds: flat, hills, pipe, "
                  "ramp, rubble, slippery, stairs, sticky)");
    check_failure(make({"world", "--preset", "rmap", "-o", "w.xml"}, dir),
                  "gaitlab: make world: unknown world 'rmap'; did you mean 'ramp'? "
                  "(worlds: flat, hills, pipe, ramp, rubble, slippery, stairs, sticky)");
    check_failure(make({"world", "--friction", "3", "-o", "w.xml"}, dir),
                  "gaitlab: make world: friction must be in [0, 1] (got 3)");
    check_failure(make({"world", "--param", "slope", "-o", "w.xml"}, dir),
                  "gaitlab: make world: 'slope': NAME=VALUE expected, the value a number "
                  "(e.g. amplitude=30)");
    check_failure(make({"actuation", "--robot", "r.xml", "--group", "pitch", "-o", "a.xml"}, dir),
                  "gaitlab: make actuation: group 'pitch': "
                  "JOINTS=CONTROLLER[:PARAM=VALUE...] expected, e.g. "
                  "pitch=sine:amplitude=40:phase=-120");
    check_failure(
        make({"actuation", "--robot", "r.xml", "--group", "head=sine", "-o", "a.xml"}, dir),
        "gaitlab: make actuation: group 'head=sine': 'head' is not a joint: say "
        "pitch, yaw, all, or joint numbers from 1 like 1 3 5");
    check_failure(
        make({"actuation", "--robot", "r.xml", "--group", "pitch=sinus", "-o", "a.xml"}, dir),
        "gaitlab: make actuation: unknown controller 'sinus'; did you mean "
        "'sine'? (built-in controllers: distributed, hindmarsh_rose, hopf, matsuoka, "
        "offset, phase_chain, sine; a template is template/NAME, a Lua controller file "
        "PATH.lua)");
    check_failure(make({"actuation", "--robot", "r.xml", "--group", "pitch=sine:amplitude=120",
                        "-o", "a.xml"},
                       dir),
                  "gaitlab: make actuation: sine.amplitude must be in [0, 90] deg (got "
                  "120)");
    check_failure(
        make({"actuation", "--robot", "nothere.xml", "--group", "pitch=sine", "-o", "a.xml"}, dir),
        "gaitlab: make actuation: --robot nothere.xml: no such file");
    check_failure(make({"sim", "--robot", "r.xml", "--world", "none.xml", "-o", "s.xml"}, dir),
                  "gaitlab: make sim: --world none.xml: no such file");
    check_failure(make({"robot", "--modules", "many", "-o", "x.xml"}, dir),
                  "gaitlab: make robot: --modules: a whole number expected (got 'many')");
    check_failure(make({"robot", "--modules", "0", "-o", "x.xml"}, dir),
                  "gaitlab: make robot: modules must be at least 1 (got 0)");
    check_failure(make({"robot", "--sensor", "laser", "-o", "x.xml"}, dir),
                  "gaitlab: make robot: unknown sensor kind 'laser' (kinds: joint, imu, "
                  "contact, range, position)");
    check_failure(make({"robot", "--modles", "3", "-o", "x.xml"}, dir),
                  "gaitlab: unknown option '--modles' for 'gaitlab make robot'; did you mean "
                  "'--modules'? (see 'gaitlab make robot --help')");
    check_failure(
        make({"sim", "--robot", "r.xml", "--world", "r.xml", "--dt", "1", "-o", "s.xml"}, dir),
        "gaitlab: make sim: dt must be in [1e-06, 0.1] s (got 1)");
    check_failure(make({}, dir),
                  "gaitlab: say what to make: gaitlab make robot|world|actuation|sim ... -o FILE "
                  "(see 'gaitlab make --help')");
    std::vector<std::string> left;
    for (const auto& e : std::filesystem::directory_iterator(dir.path))
        left.push_back(e.path().filename().string());
    CHECK(left == std::vector<std::string>{"r.xml"});
}

TEST_CASE("make never loses a file: -o is no input, and replaces only a file of its kind",
          "[cli][make]") {
    TempDir dir("make_keep");
    REQUIRE(make({"robot", "-o", "r.xml"}, dir).status == 0);
    REQUIRE(make({"world", "-o", "w.xml"}, dir).status == 0);
    gaitlab::test::write_text(dir / "notes.xml", "mine");
    const std::string robot = gaitlab::test::read_text(dir / "r.xml");
    // the simulation written over the robot it names
    check_failure(make({"sim", "--robot", "r.xml", "--world", "w.xml", "-o", "./r.xml"}, dir),
                  "gaitlab: make sim: -o ./r.xml is the --robot file, which would be "
                  "lost: write to another file");
    check_failure(make({"robot", "-o", "notes.xml"}, dir),
                  "gaitlab: make robot: -o notes.xml exists and is not a robot file, so "
                  "it would be lost: write to another file, or add --force to replace it");
    check_failure(
        make({"actuation", "--robot", "r.xml", "--group", "all=sine", "-o", "w.xml"}, dir),
        "gaitlab: make actuation: -o w.xml exists and is not an actuation "
        "file, so it would be lost: write to another file, or add --force to replace "
        "it");
    check_failure(make({"robot", "-o", ""}, dir),
                  "gaitlab: make robot: -o: a file name "
                  "expected");
    CHECK(gaitlab::test::read_text(dir / "notes.xml") == "mine");
    CHECK(gaitlab::test::read_text(dir / "r.xml") == robot);
    CHECK(gaitlab::read_environment(dir / "w.xml").placements.empty());
    // a part made again replaces the old one; --force replaces anything
    Output r = make({"robot", "--modules", "3", "-o", "r.xml"}, dir);
    CHECK(r.status == 0);
    CHECK(gaitlab::read_robot(dir / "r.xml").joints.size() == 3);
    r = make({"robot", "--force", "-o", "notes.xml"}, dir);
    CHECK(r.status == 0);
    CHECK(gaitlab::read_robot(dir / "notes.xml").joints.size() == 8);
}

TEST_CASE("make refuses a parameter given twice instead of keeping the last", "[cli][make]") {
    TempDir dir("make_twice");
    REQUIRE(make({"robot", "-o", "r.xml"}, dir).status == 0);
    check_failure(
        make({"world", "--param", "friction=0.5", "--friction", "0.6", "-o", "w.xml"}, dir),
        "gaitlab: make world: friction is given twice (--friction and --param "
        "friction=...): give it once");
    check_failure(make({"world", "--preset", "ramp", "--param", "slope=3", "--param", "slope=4",
                        "-o", "w.xml"},
                       dir),
                  "gaitlab: make world: 'slope' is given twice (slope=3 and slope=4): "
                  "give it once");
    check_failure(make({"actuation", "--robot", "r.xml", "--group",
                        "all=sine:amplitude=1:amplitude=2", "-o", "a.xml"},
                       dir),
                  "gaitlab: make actuation: group 'all=sine:amplitude=1:amplitude=2': "
                  "'amplitude' is given twice (amplitude=1 and amplitude=2): give it once");
    check_failure(
        make({"actuation", "--robot", "r.xml", "--group", "all,3=sine", "-o", "a.xml"}, dir),
        "gaitlab: make actuation: group 'all,3=sine': 'all' stands alone: say "
        "pitch, yaw or all, or joint numbers like 1 3 5, not both (got 'all 3')");
    CHECK(!std::filesystem::exists(dir / "w.xml"));
    CHECK(!std::filesystem::exists(dir / "a.xml"));
}

TEST_CASE("make sim takes every duration a simulation file takes, and refuses the rest as it does",
          "[cli][make]") {
    TempDir dir("make_duration");
    REQUIRE(make({"robot", "-o", "r.xml"}, dir).status == 0);
    REQUIRE(make({"world", "-o", "w.xml"}, dir).status == 0);
    // beyond the 1e6 s make once stopped at, and 0: a file loads both
    for (const char* duration : {"2000000", "0", "9e12"}) {
        INFO(duration);
        const Output r = make({"sim", "--robot", "r.xml", "--world", "w.xml", "--duration",
                               duration, "--no-record", "-o", "s.xml"},
                              dir);
        CHECK(r.status == 0);
        CHECK(r.err.empty());
        CHECK(gaitlab::read_simulation(dir / "s.xml").duration == std::stod(duration));
    }
    // 2^53 ticks at dt: the file's limit, said in the file's words
    check_failure(
        make({"sim", "--robot", "r.xml", "--world", "w.xml", "--duration", "1e16", "-o", "t.xml"},
             dir),
        "gaitlab: make sim: duration must be in [0, 9.0072e+12] s at dt = 0.001 s (got "
        "1e+16 s)");
    check_failure(make({"sim", "--robot", "r.xml", "--world", "w.xml", "--duration", "1e10", "--dt",
                        "1e-6", "-o", "t.xml"},
                       dir),
                  "gaitlab: make sim: duration must be in [0, 9.0072e+09] s at dt = 1e-06 s (got "
                  "1e+10 s)");
    check_failure(
        make({"sim", "--robot", "r.xml", "--world", "w.xml", "--duration", "-1", "-o", "t.xml"},
             dir),
        "gaitlab: make sim: duration must be a non-negative number of seconds (got -1)");
    CHECK(!std::filesystem::exists(dir / "t.xml"));
}
