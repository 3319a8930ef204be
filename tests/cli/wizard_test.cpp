// `gaitlab new` (cli/wizard.cpp) with answers piped on stdin: the defaults, a new controller
// typed in, garbage at every kind of question, the end of input half-way, a folder that is
// taken. Outcomes are checked: the files load and run with `gaitlab run`, the robot moved, the
// controller has the parameters typed, and an interrupted wizard left nothing.
#include <catch2/catch.hpp>

#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "gaitlab/xml.h"
#include "run_gaitlab.h"

using gaitlab::test::Output;
using gaitlab::test::read_text;
using gaitlab::test::run_gaitlab;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

namespace fs = std::filesystem;

// the distance in "NAME: moved D m ..." (-1 if absent)
double moved(const std::string& out, const std::string& robot) {
    std::smatch m;
    const std::regex re(robot + R"(: moved ([0-9.]+) m)");
    return std::regex_search(out, m, re) ? std::stod(m[1]) : -1;
}

std::vector<std::string> entries(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir))
        out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

// the answers, one a line
std::string lines(const std::vector<std::string>& answers) {
    std::string out;
    for (const std::string& a : answers)
        out += a + "\n";
    return out;
}

}  // namespace

TEST_CASE("gaitlab new --defaults writes a project that runs and moves", "[cli][wizard]") {
    TempDir dir("wizard_defaults");
    // without DIR: a folder named after the robot
    const Output r = run_gaitlab({"new", "--defaults"}, dir.str());
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());
    // no questions, the files listed, the run's result and where it was recorded
    CHECK(r.out.find("[") == std::string::npos);
    for (const char* f :
         {"robot.xml", "actuation.xml", "environment.xml", "simulation.xml", "run.lua"}) {
        CHECK(fs::is_regular_file(dir.path / "snake" / f));
        CHECK_THAT(r.out, Catch::Contains(std::string("snake/") + f));
    }
    CHECK(moved(r.out, "snake") > 0.05);
    CHECK_THAT(r.out, Catch::Contains("The recording is in snake/runs/snake-"));
    CHECK(entries(dir.path / "snake" / "runs").size() == 1);
    const gaitlab::RobotSpec robot = gaitlab::read_robot(dir / "snake/robot.xml");
    CHECK(robot.name == "snake");
    CHECK(robot.joints.size() == 8);
    CHECK(gaitlab::read_simulation(dir / "snake/simulation.xml").duration == 10);

    // the same files with gaitlab run: the simulation file and run.lua, the same distance
    const Output xml = run_gaitlab({"run", "--no-record", "snake/simulation.xml"}, dir.str());
    CHECK(xml.status == 0);
    CHECK(moved(xml.out, "snake") == moved(r.out, "snake"));
    const Output lua = run_gaitlab({"run", "--no-record", "snake/run.lua"}, dir.str());
    CHECK(lua.status == 0);
    CHECK(moved(lua.out, "snake") == moved(r.out, "snake"));

    // snake is taken now: snake-2 (a 1 s run, not recorded)
    const Output again = run_gaitlab({"new"}, dir.str(), std::string(11, '\n') + "1\n\n\nno\n");
    CHECK(again.status == 0);
    CHECK(entries(dir.path) == std::vector<std::string>{"snake", "snake-2"});
}

TEST_CASE("the commands the wizard prints can be pasted into a shell", "[cli][wizard]") {
    // a folder with a space printed "gaitlab run my snake/run.lua", which a shell splits, and a
    // folder holding $(...) printed a command substitution for the user to paste
    TempDir dir("wizard_quoted");
    const Output r = run_gaitlab({"new", "my $(touch x) snake", "--defaults"}, dir.str());
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.out, Catch::Contains("Run it again: gaitlab run 'my $(touch x) snake/run.lua'"));
    CHECK_THAT(r.out, Catch::Contains("runs it all: gaitlab run 'my $(touch x) snake/run.lua'"));
    CHECK_FALSE(fs::exists(dir.path / "x"));
}

TEST_CASE("pressing Enter at every question gives the defaults", "[cli][wizard]") {
    TempDir dir("wizard_enter");
    const Output r = run_gaitlab({"new", "p", "--record-not-an-option"}, dir.str(), "");
    CHECK(r.status == 2);  // (strict options: checked before any question)
    const Output e = run_gaitlab({"new", "p"}, dir.str(), std::string(15, '\n'));
    INFO(e.out << e.err);
    REQUIRE(e.status == 0);
    CHECK_THAT(e.out, Catch::Contains("Robot name [snake]: "));
    CHECK_THAT(e.out, Catch::Contains("Number of modules [8]: "));
    CHECK(moved(e.out, "snake") > 0.05);
}

TEST_CASE("a new controller with two parameters is written as typed and moves the robot",
          "[cli][wizard]") {
    TempDir dir("wizard_new_controller");
    const std::string answers = lines({
        "worm",                              // robot name
        "6",                                 // modules
        "",                                  // pitch-pitch
        "imu",                               // sensors
        "3",                                 // a new controller
        "wave",                              // its name
        "2",                                 // two parameters
        "amp",        "35",  "0 60", "deg",  // name, initial value, range, unit
        "freq",       "0.8", "0 3",  "Hz",
        "time angle",  // per-joint values
        "",            // joints: all
        "",            // no other controller
        "",            // flat
        "0.9",         // friction
        "4",           // seconds
        "",            // dt
        "",            // control_every
        "no",          // no recording
    });
    const Output r = run_gaitlab({"new", "w"}, dir.str(), answers);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    CHECK(r.out.find("  ! ") == std::string::npos);
    CHECK(moved(r.out, "worm") > 0.02);
    CHECK(!fs::exists(dir.path / "w" / "runs"));
    CHECK_THAT(r.out, Catch::Contains("w/controllers/wave.lua"));

    // the controller as a Lua script sees it: its parameters as typed
    write_text(dir / "check.lua", R"(
local class = gaitlab.controller.load(arg[1])
local ctl = class{}
local names = {}
for name, p in pairs(ctl:params()) do names[#names + 1] = name end
table.sort(names)
for _, name in ipairs(names) do
  local p = ctl:params()[name]
  print(name, p.value, p.min, p.max, p.unit)
end
print(class.name, ctl:values().time ~= nil, ctl:values().angle ~= nil)
)");
    const Output c =
        run_gaitlab({"run", "--no-record", "check.lua", "w/controllers/wave.lua"}, dir.str());
    INFO(c.err);
    CHECK(c.out == "amp\t35.0\t0.0\t60.0\tdeg\nfreq\t0.8\t0.0\t3.0\tHz\nwave\ttrue\ttrue\n");

    // the actuation drives all joints with that file; the robot carries the imu
    const gaitlab::ActuationSpec act = gaitlab::read_actuation(dir / "w/actuation.xml");
    REQUIRE(act.groups.size() == 1);
    CHECK(act.groups[0].role == "pitch");  // all the joints of a pitch-pitch chain
    CHECK(act.groups[0].controller.name == "controllers/wave.lua");
    CHECK(gaitlab::read_robot(dir / "w/robot.xml").sensors.at(0).name == "imu6");
    CHECK(gaitlab::read_environment(dir / "w/environment.xml").world.floor.friction == 0.9);
    const Output run = run_gaitlab({"run", "--no-record", "w/simulation.xml"}, dir.str());
    CHECK(moved(run.out, "worm") == moved(r.out, "worm"));
}

TEST_CASE("garbage answers are explained and asked again", "[cli][wizard]") {
    TempDir dir("wizard_garbage");
    const std::string answers = lines({
        "",  // name: snake
        "many",
        "0",
        "5",  // modules
        "pitch-roll",
        "9",
        "2",  // connection: pitch-yaw
        "laser imu:0",
        "imu:9",
        "imu:3 position",  // sensors
        "4",
        "built-in",  // kind of controller
        "sinus",
        "sine",  // built-in
        "amplitude=200",
        "amplitud=3",
        "amplitude",
        "amplitude=30 phase=-120",
        "head",
        "9",
        "",  // joints: pitch
        "maybe",
        "yes",  // another controller
        "2",    // a template
        "cpg",
        "cpg_chain",
        "coupling=1000",
        "",
        "yaw",  // joints
        "",     // no more
        "moon",
        "ramp",  // world
        "2",
        "0.5",  // friction
        "-1",
        "3",  // seconds
        "0",
        "",  // dt
        "x",
        "",  // control_every
        "sure",
        "no",  // recording
    });
    const Output r = run_gaitlab({"new", "g"}, dir.str(), answers);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    // one explanation per bad answer, in the engine's words where it has them
    for (const char* line : {
             "  ! 'many': a whole number from 1 to 1000 expected\n",
             "  ! 'pitch-roll' is not one of the choices (pitch-pitch, pitch-yaw, yaw-yaw)\n",
             "  ! '9': choose a number from 1 to 3, or a name\n",
             "  ! unknown sensor kind 'laser' (kinds: joint, imu, contact, range, position)\n",
             "  ! '4': choose a number from 1 to 3, or a name\n",
             "  ! 'sinus' is not one of the choices; did you mean 'sine'?",
             "  ! sine.amplitude must be in [0, 90] deg (got 200)\n",
             "  ! 'head' is not a joint: say pitch, yaw, all, or joint numbers from 1 like 1 3 5\n",
             "  ! 'maybe': answer yes or no\n",
             "  ! 'moon' is not one of the choices",
             "  ! friction must be in [0, 1] (got 2)\n",
             "  ! 'x': a whole number from 1 to 1000000 expected\n",
             "  ! 'sure': answer yes or no\n",
         }) {
        CHECK_THAT(r.out, Catch::Contains(line));
    }
    // 22 bad answers, 22 explanations
    size_t count = 0;
    for (size_t at = r.out.find("  ! "); at != std::string::npos; at = r.out.find("  ! ", at + 1))
        ++count;
    CHECK(count == 22);
    // what was finally answered
    const gaitlab::RobotSpec robot = gaitlab::read_robot(dir / "g/robot.xml");
    CHECK(robot.joints.size() == 5);
    CHECK(robot.sensors.size() == 2);
    const gaitlab::ActuationSpec act = gaitlab::read_actuation(dir / "g/actuation.xml");
    REQUIRE(act.groups.size() == 2);
    CHECK(act.groups[0].role == "pitch");
    CHECK(act.groups[1].role == "yaw");
    CHECK(act.groups[1].controller.name == "controllers/cpg_chain.lua");
    CHECK(fs::is_regular_file(dir.path / "g/controllers/cpg_chain.lua"));
    CHECK(gaitlab::read_simulation(dir / "g/simulation.xml").duration == 3);
    CHECK(moved(r.out, "snake") >= 0);
}

TEST_CASE("a pitch-yaw chain of more than 12 modules is told of the Newton steps it gets",
          "[cli][wizard]") {
    TempDir dir("wizard_long_chain");
    // name, modules, connection, then sensors .. friction as offered, 1 s simulated
    const auto answers = [](const std::string& modules, const std::vector<std::string>& rest) {
        std::vector<std::string> a = {"", modules, "2", "", "", "", "", "", "", "", "", "1"};
        a.insert(a.end(), rest.begin(), rest.end());
        return lines(a);
    };
    // 16 modules: the usual questions and defaults, a line on the Newton steps; the file leaves
    // newton_steps to the simulation, which gives the chain kLongChainNewtonSteps, and the run is
    // quiet
    const Output r = run_gaitlab({"new", "long"}, dir.str(), answers("16", {"", "", "no"}));
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.out, Catch::Contains("A pitch-yaw chain of more than 12 modules gets " +
                                      std::to_string(gaitlab::kLongChainNewtonSteps) +
                                      " Newton steps in every physics step"));
    CHECK_THAT(r.out, Catch::Contains("Time step, s (smaller: more accurate, slower) [0.001]: "));
    CHECK_THAT(r.out, Catch::Contains("Physics steps between two controller steps [30]: "));
    CHECK(r.out.find("Solver iterations") == std::string::npos);
    const gaitlab::SimulationOptions o =
        gaitlab::read_simulation(dir / "long/simulation.xml").options;
    CHECK(o.dt == 0.001);
    CHECK(o.solver_iterations == 20);
    CHECK(o.newton_steps == gaitlab::kAutomaticNewtonSteps);
    CHECK(r.err.find("warning") == std::string::npos);
    CHECK(moved(r.out, "snake") >= 0);
    // a coarser step answered, after a garbage answer: written as answered, and the run warns
    // naming it
    const Output coarse =
        run_gaitlab({"new", "coarse"}, dir.str(), answers("13", {"fast", "0.002", "", "no"}));
    INFO(coarse.out << coarse.err);
    REQUIRE(coarse.status == 0);
    CHECK_THAT(coarse.out, Catch::Contains("  ! 'fast': "));
    CHECK(gaitlab::read_simulation(dir / "coarse/simulation.xml").options.dt == 0.002);
    CHECK_THAT(coarse.err, Catch::Contains("dt = 2 ms is above 1 ms with newton_steps = " +
                                           std::to_string(gaitlab::kLongChainNewtonSteps) +
                                           ": robot "
                                           "'snake' has 13 joints"));
    // 12 modules: the usual questions and defaults, no such line
    const Output twelve = run_gaitlab({"new", "twelve"}, dir.str(), answers("12", {"", "", "no"}));
    INFO(twelve.out << twelve.err);
    REQUIRE(twelve.status == 0);
    CHECK(twelve.out.find("Newton") == std::string::npos);
    CHECK_THAT(twelve.out,
               Catch::Contains("Time step, s (smaller: more accurate, slower) [0.001]: "));
    const gaitlab::SimulationOptions d =
        gaitlab::read_simulation(dir / "twelve/simulation.xml").options;
    CHECK(d.dt == 0.001);
    CHECK(d.solver_iterations == 20);
    CHECK(twelve.err.find("warning") == std::string::npos);
}

TEST_CASE("the end of input half-way leaves nothing behind", "[cli][wizard]") {
    TempDir dir("wizard_eof");
    // after a few answers, and in the middle of a new controller's parameters
    for (const std::string& answers :
         {lines({"snake", "8"}), lines({"", "", "", "", "new", "gait", "2", "amp", "10"}),
          lines(std::vector<std::string>(14, ""))}) {
        INFO(answers);
        const Output r = run_gaitlab({"new"}, dir.str(), answers);
        CHECK(r.status == 1);
        CHECK_THAT(r.err, Catch::StartsWith("gaitlab: end of input at '"));
        CHECK_THAT(r.err, Catch::EndsWith("'; nothing was written\n"));
        CHECK(entries(dir.path).empty());
        const Output d = run_gaitlab({"new", "given"}, dir.str(), answers);
        CHECK(d.status == 1);
        CHECK(entries(dir.path).empty());
    }
}

TEST_CASE("piped answers are echoed with control bytes written out", "[cli][wizard]") {
    // a file of answers holding escape sequences: the echo of each answer and the message
    // refusing it show the bytes as \xNN, and the terminal gets no control byte but line ends
    TempDir dir("wizard_escape");
    const Output r = run_gaitlab({"new", "esc"}, dir.str(),
                                 lines({"", "\x1b[31mmany\x1b]0;title\x07", "4", "2", "", "", "",
                                        "", "", "", "", "", "1", "", "", "no"}));
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.out, Catch::Contains("\\x1b[31mmany\\x1b]0;title\\x07\n"));
    for (const char c : r.out)
        CHECK((static_cast<unsigned char>(c) >= 0x20 || c == '\n'));
}

TEST_CASE("a project folder that exists and is not empty is refused", "[cli][wizard]") {
    TempDir dir("wizard_taken");
    fs::create_directories(dir.path / "taken");
    write_text(dir / "taken/notes.txt", "mine");
    write_text(dir / "file", "mine");
    Output r = run_gaitlab({"new", "--defaults", "taken"}, dir.str());
    CHECK(r.status == 1);
    CHECK(r.out.empty());  // refused before any question
    CHECK(r.err == "gaitlab: new: taken exists and is not empty: choose another folder\n");
    CHECK(entries(dir.path / "taken") == std::vector<std::string>{"notes.txt"});
    r = run_gaitlab({"new", "--defaults", "file"}, dir.str());
    CHECK(r.err == "gaitlab: new: file exists and is not a folder: choose another folder\n");
    CHECK(read_text(dir / "file") == "mine");
    // an empty folder is fine
    fs::create_directories(dir.path / "empty");
    r = run_gaitlab({"new", "--defaults", "empty"}, dir.str());
    CHECK(r.status == 0);
    CHECK(fs::is_regular_file(dir.path / "empty/simulation.xml"));
    CHECK(entries(dir.path) == std::vector<std::string>{"empty", "file", "taken"});
}

TEST_CASE("garbage answers about a new controller are explained and asked again", "[cli][wizard]") {
    TempDir dir("wizard_garbage_new");
    const std::string answers = lines({
        std::string(300, 'x'),
        "bob",  // robot name
        "3",    // modules
        "",
        "",  // pitch-pitch, no sensors
        "new",
        "2fast",
        "end",
        "gait",  // controller name
        "-1",
        "99",
        "1",  // how many parameters
        "joints",
        "amp",  // parameter name ('joints' is reserved)
        "big",
        "30",  // initial value
        "5",
        "50 60",
        "0 60",  // range
        "",      // unit: deg
        "time time",
        "time",  // per-joint values
        "1 x",
        "1 2",  // joints
        "",
        "",
        "",
        "1",
        "",
        "",
        "no",
    });
    const Output r = run_gaitlab({"new", "b"}, dir.str(), answers);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    for (const char* line : {
             "  ! '2fast' cannot name a controller: letters, digits and _, not starting with a "
             "digit (e.g. my_gait)\n",
             "  ! 'end' is a word Lua keeps for itself: choose another name\n",
             "  ! '-1': a whole number from 0 to 20 expected\n",
             "  ! 'big': a number expected\n",
             "  ! two numbers expected: MIN MAX\n",
             "  ! 'time' is already a parameter or value of the controller\n",
             "  ! 'x' is not a joint",
         }) {
        CHECK_THAT(r.out, Catch::Contains(line));
    }
    size_t count = 0;
    for (size_t at = r.out.find("  ! "); at != std::string::npos; at = r.out.find("  ! ", at + 1))
        ++count;
    CHECK(count == 11);
    CHECK(gaitlab::read_robot(dir / "b/robot.xml").name == "bob");
    const gaitlab::ActuationSpec act = gaitlab::read_actuation(dir / "b/actuation.xml");
    REQUIRE(act.groups.size() == 1);
    CHECK(act.groups[0].joints == std::vector<int>{0, 1});
    CHECK(act.groups[0].controller.name == "controllers/gait.lua");
    CHECK_THAT(read_text(dir / "b/controllers/gait.lua"),
               Catch::Contains("amp = { 30, min = 0, max = 60, unit = \"deg\" },"));
    CHECK(moved(r.out, "bob") >= 0);
}

TEST_CASE("endless or always-refused piped answers stop the wizard", "[cli][wizard]") {
    TempDir dir("wizard_endless");
    // `yes | gaitlab new`: 'y' names the robot, then is refused as a number of modules; after
    // ten refusals in a row the wizard stops instead of asking forever
    const Output yes = run_gaitlab(
        {"new", "p"}, dir.str(), std::string(1000, 'y') + "\n" + [] {
            std::string s;
            for (int i = 0; i < 500; ++i)
                s += "y\n";
            return s;
        }());
    CHECK(yes.status == 1);
    CHECK(yes.err ==
          "gaitlab: 10 answers to 'Number of modules' were refused in a row (see the "
          "'!' lines); nothing was written\n");
    // nine refusals, then a good answer: the wizard goes on
    std::string nine = "\n";
    for (int i = 0; i < 9; ++i)
        nine += "x\n";
    const Output ok =
        run_gaitlab({"new", "q"}, dir.str(), nine + "3\n" + std::string(9, '\n') + "1\n\n\nno\n");
    INFO(ok.out << ok.err);
    CHECK(ok.status == 0);
    CHECK(gaitlab::read_robot(dir / "q/robot.xml").joints.size() == 3);
    // an answer that never ends (`< /dev/zero`): stopped at 64 KiB, not read into the memory
    const Output zero = run_gaitlab({"new", "z"}, dir.str(), std::string(100000, '\0'));
    CHECK(zero.status == 1);
    CHECK_THAT(zero.err, Catch::EndsWith("gaitlab: the answer to 'Robot name' is longer than "
                                         "65536 bytes; nothing was written\n"));
    // a NUL byte is shown as \x00, and the line after it is not glued to it
    const Output nul = run_gaitlab({"new", "n"}, dir.str(), std::string("a\0b\n", 4));
    CHECK_THAT(nul.out, Catch::Contains("Robot name [snake]: a\\x00b\n  ! "));
    CHECK(entries(dir.path) == std::vector<std::string>{"q"});
}

TEST_CASE("a project folder that cannot be made is refused before the first question",
          "[cli][wizard]") {
    TempDir dir("wizard_where");
    write_text(dir / "file", "mine");
    fs::create_symlink("nowhere", dir.path / "dangling");
    Output r = run_gaitlab({"new", "dangling"}, dir.str(), "");
    CHECK(r.status == 1);
    CHECK(r.out.empty());
    CHECK(r.err ==
          "gaitlab: new: dangling is a symbolic link to nowhere, which does not exist: "
          "choose another folder\n");
    r = run_gaitlab({"new", "file/p"}, dir.str(), "");
    CHECK(r.out.empty());
    CHECK(r.err ==
          "gaitlab: new: cannot create file/p: " + (dir / "file") + " is a file, not a folder\n");
    CHECK(read_text(dir / "file") == "mine");
    // a folder the system refuses though access() allows it (root may "write" in /proc): the
    // questions were all asked first, and the answers lost
    r = run_gaitlab({"new", "/proc/gaitlab_project"}, dir.str(), "");
    CHECK(r.status == 1);
    CHECK(r.out.empty());
    CHECK_THAT(r.err, Catch::StartsWith("gaitlab: new: cannot create /proc/gaitlab_project: "));
    // folders that do not exist yet are made; a trailing '/' names the same folder
    r = run_gaitlab({"new", "--defaults", "a/b/"}, dir.str());
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(fs::is_regular_file(dir.path / "a/b/simulation.xml"));
    // a link to an empty folder: the project goes into that folder
    fs::create_directories(dir.path / "target");
    fs::create_directory_symlink("target", dir.path / "link");
    r = run_gaitlab({"new", "--defaults", "link"}, dir.str());
    CHECK(r.status == 0);
    CHECK(fs::is_symlink(dir.path / "link"));
    CHECK(fs::is_regular_file(dir.path / "target/simulation.xml"));
}

TEST_CASE("a template chosen after a new controller of its name gets a file of its own",
          "[cli][wizard]") {
    TempDir dir("wizard_same_name");
    const std::string answers = lines({
        "",         "",     "",  "",         // snake, 8 modules, pitch-pitch, no sensors
        "new",      "sine", "0", "",         // a new controller called sine, no parameters
        "1 2 3 4",  "yes",                   // its joints; another
        "template", "sine", "",  "5 6 7 8",  // the sine template on the others
        "",         "",     "",  "1",       "", "", "no",
    });
    const Output r = run_gaitlab({"new", "p"}, dir.str(), answers);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    CHECK(r.out.find("  ! ") == std::string::npos);
    CHECK_THAT(read_text(dir / "p/controllers/sine.lua"), Catch::Contains("name = \"sine\""));
    CHECK_THAT(read_text(dir / "p/controllers/sine_2.lua"), Catch::Contains("my_sine"));
    const gaitlab::ActuationSpec act = gaitlab::read_actuation(dir / "p/actuation.xml");
    REQUIRE(act.groups.size() == 2);
    CHECK(act.groups[0].controller.name == "controllers/sine.lua");
    CHECK(act.groups[1].controller.name == "controllers/sine_2.lua");
    CHECK(moved(r.out, "snake") >= 0);
}

TEST_CASE(
    "a second controller on the same joints is refused naming the first, and is not "
    "offered them",
    "[cli][wizard]") {
    // the refusal named a controller 'offset' the project did not have (the new controller stood
    // in as one while its file was not written), and the second controller's default joints
    // were the first's, so Enter could never get past the question
    TempDir dir("wizard_same_group");
    const std::string answers = lines({
        "nw",       "4",    "",  "",  // 4 modules, pitch-pitch, no sensors
        "new",      "foo",  "0", "",  // a new controller foo, no parameters
        "all",      "yes",            // on every joint; another
        "built-in", "sine", "",       // sine
        "all",                        // on the same joints: refused
        "",                           // Enter: no default to take
        "1 2",      "no",   "",  "", "", "1", "", "", "no",
    });
    const Output r = run_gaitlab({"new", "p"}, dir.str(), answers);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.out, Catch::Contains("! controller 'sine' cannot drive joints 1, 2, 3, 4 of "
                                      "robot 'nw': controller 'foo' already drives exactly "
                                      "these joints"));
    CHECK(r.out.find("'offset'") == std::string::npos);
    CHECK_THAT(r.out, Catch::Contains("Joints [none]: \n  ! no joints given"));
    const gaitlab::ActuationSpec act = gaitlab::read_actuation(dir / "p/actuation.xml");
    REQUIRE(act.groups.size() == 2);
    CHECK(act.groups[1].controller.name == "sine");
}

TEST_CASE("mixed joint words, twice-given parameters and three-number ranges are explained",
          "[cli][wizard]") {
    TempDir dir("wizard_words");
    const std::string answers = lines({
        "",
        "4",
        "",
        "",
        "",
        "",
        "amplitude=10 amplitude=20",
        "amplitude=20",  // built-in sine
        "all 1",
        "",  // joints
        "",
        "",
        "",
        "1",
        "",
        "",
        "no",
    });
    const Output r = run_gaitlab({"new", "p"}, dir.str(), answers);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.out, Catch::Contains("  ! 'amplitude' is given twice (amplitude=10 and "
                                      "amplitude=20): give it once\n"));
    CHECK_THAT(r.out, Catch::Contains("  ! 'all' stands alone: say pitch, yaw or all, or joint "
                                      "numbers like 1 3 5, not both (got 'all 1')\n"));
    const gaitlab::ActuationSpec act = gaitlab::read_actuation(dir / "p/actuation.xml");
    REQUIRE(act.groups.size() == 1);
    const auto& params = act.groups[0].controller.params;
    CHECK(std::find(params.begin(), params.end(), std::make_pair(std::string("amplitude"), 20.0)) !=
          params.end());

    // a range of three numbers is refused as a whole; commas separate like spaces
    const Output n =
        run_gaitlab({"new", "q"}, dir.str(),
                    lines({"", "", "", "", "new", "g", "1", "a", "1", "0 1 2", "0,,2"}));
    CHECK(n.status == 1);  // (the end of input at the unit)
    CHECK_THAT(n.out, Catch::Contains("  ! '0 1 2': two numbers expected: MIN MAX\n"));
    CHECK_THAT(n.out, Catch::Contains("range of a, as MIN MAX [0 90]: 0,,2\n  unit of a"));
}
