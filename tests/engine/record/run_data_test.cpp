// Reading run folders (engine/src/record/run_data.cpp): lookup by name and by kind + value + joint,
// time ranges, a truncated last line, folders that are not runs, malformed files.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>
#include <set>

#include <fmt/format.h>

#include "engine/sim_support.h"
#include "gaitlab/error.h"
#include "gaitlab/plot.h"
#include "gaitlab/recorder.h"
#include "gaitlab/run_data.h"
#include "temp_dir.h"

using namespace gaitlab;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;
namespace fs = std::filesystem;

TEST_CASE("series by name, by kind + value + joint, and over a time range", "[run_data]") {
    TempDir tmp("run_data_get");
    RunData run(test::record_run(tmp / "run", 1));
    CHECK(run.rows() == 34);
    const SeriesData a = run.get("sine.angle[2]");
    REQUIRE(a.time.size() == 34);
    CHECK(a.info.kind == SeriesKind::controller);
    CHECK(a.info.joint == 2);
    CHECK(a.time[0] == 0);
    CHECK(a.time[33] == Approx(0.99));
    // the sine's own value: A sin(2 pi f t + (m - 1) phase) at the last control step
    CHECK(a.values[33] == Approx(40 * std::sin(2 * kPi * 0.5 * 0.99 + kPi * 120 / 180)));

    // before the first step no servo has acted (Bullet's feedback starts at zero)
    for (int j = 1; j <= 4; ++j)
        CHECK(run.get(fmt::format("snake.torque[{}]", j)).values[0] == 0);
    CHECK(run.find(SeriesKind::robot, "angle", 3).name == "snake.angle[3]");
    CHECK(run.find(SeriesKind::robot, "energy", 0).name == "snake.energy");
    CHECK(run.find(SeriesKind::controller, "amplitude", 0, "sine").name == "sine.amplitude");
    CHECK_THROWS_WITH(run.find(SeriesKind::robot, "angel", 3),
                      "no robot series 'angel' of joint 3; did you mean 'angle'?");
    CHECK_THROWS_WITH(run.find(SeriesKind::sensor, "range", 1),
                      "no sensor series 'range' of joint 1");
    // the value exists for other joints: said so, not "did you mean 'angle'?"
    CHECK_THROWS_WITH(run.find(SeriesKind::robot, "angle", 0),
                      "no robot series 'angle': 'angle' is per joint (joint = 1 to 4)");
    CHECK_THROWS_WITH(run.find(SeriesKind::robot, "angle", 7),
                      "no robot series 'angle' of joint 7: 'angle' is per joint (joint = 1 to 4)");
    CHECK_THROWS_WITH(run.find(SeriesKind::robot, "com.x", 2),
                      "no robot series 'com.x' of joint 2: 'com.x' is not per joint (leave the "
                      "joint out)");

    const SeriesData r = run.get("snake.com.x", 0.25, 0.5);
    REQUIRE(r.time.size() == 8);  // 0.27, 0.30, ..., 0.48
    CHECK(r.time.front() == Approx(0.27));
    CHECK(r.time.back() == Approx(0.48));

    CHECK_THROWS_WITH(run.get("snake.angle[9]"),
                      "unknown series 'snake.angle[9]'; did you mean 'snake.angle[1]', "
                      "'snake.angle[2]' or 'snake.angle[3]'?");
    CHECK(run.select({"snake.angle[*]"}).size() == 4);
    CHECK(run.select({"controller"}).size() == 5 + 8);
    CHECK(run.select({"sine.amplitude", "sine.*"}).front() == "sine.amplitude");
    CHECK_THROWS_WITH(run.select({"sensor"}), "the run has no sensor series");
    CHECK_THROWS_WITH(run.select({"snake.com.q*"}),
                      "no series matches 'snake.com.q*'; did you mean 'snake.com.x', "
                      "'snake.com.y' or 'snake.com.z'?");

    run.write_csv(tmp / "two.csv", {"snake.com.x", "sine.amplitude"}, 0, 0.03);
    const std::string csv = read_text(tmp / "two.csv");
    CHECK_THAT(csv, Catch::StartsWith("time,snake.com.x,sine.amplitude\n0,"));
    CHECK_THAT(csv, Catch::EndsWith(",40\n"));
}

TEST_CASE("a last line cut short is dropped, malformed lines name file and line", "[run_data]") {
    TempDir tmp("run_data_truncated");
    const std::string dir = test::record_run(tmp / "run", 1);
    const std::string data = read_text(dir + "/data.csv");
    // a process killed while writing leaves part of a line
    write_text(dir + "/data.csv", data.substr(0, data.size() - 25));
    RunData run(dir);
    CHECK(run.rows() == 33);
    CHECK(run.truncated());
    CHECK(run.get("snake.com.z").values.size() == 33);

    // a broken line that is not the last one is an error
    std::string broken = data;
    const size_t line3 = broken.find('\n', broken.find('\n') + 1) + 1;
    broken.insert(line3 + 1, "x");
    write_text(dir + "/data.csv", broken);
    CHECK_THROWS_WITH(RunData(dir).get("snake.com.z"),
                      dir + "/data.csv:3: column 'time': number expected, got '0x.03'");
    write_text(dir + "/data.csv", data.substr(0, data.find('\n') + 1) + "0,1,2\n");
    CHECK_THROWS_WITH(RunData(dir).get("snake.com.z"),
                      dir + "/data.csv:2: 81 fields expected, got 3");
    // a quote that never closes in series.csv swallowed the lines after it, and data.csv was
    // blamed for having more columns than series
    {
        write_text(dir + "/data.csv", data);
        const std::string series = read_text(dir + "/series.csv");
        std::string quoted = series;
        const size_t third = quoted.find('\n', quoted.find('\n') + 1) + 1;
        quoted.insert(third, "\"");
        write_text(dir + "/series.csv", quoted);
        CHECK_THROWS_WITH(RunData(dir), dir +
                                            "/series.csv:3: a quoted field that never ends (a "
                                            "'\"' without its closing '\"')");
        write_text(dir + "/series.csv", series);
    }
    write_text(dir + "/data.csv", "time,a\n");
    CHECK_THROWS_WITH(RunData(dir),
                      dir +
                          "/data.csv:1: 81 columns expected (time and the 80 series of "
                          "series.csv), got 2");
    write_text(dir + "/run.json", "{\"format\": \"gaitlab run\",\n \"status\": }");
    CHECK_THROWS_WITH(RunData(dir), dir + "/run.json:2: JSON value expected, got '}'");
    write_text(dir + "/run.json", "[1, 2]");
    CHECK_THROWS_WITH(RunData(dir),
                      dir +
                          "/run.json:1: not a gaitlab run description (an object with "
                          "\"format\": \"gaitlab run\" expected)");
}

TEST_CASE("a folder that is not a run says what it lacks", "[run_data]") {
    TempDir tmp("run_data_missing");
    CHECK_THROWS_AS(RunData(tmp / "nothing"), IoError);
    CHECK_THROWS_WITH(RunData(tmp / "nothing"), "no run folder at " + (tmp / "nothing"));
    write_text(tmp / "file.txt", "x");
    CHECK_THROWS_WITH(RunData(tmp / "file.txt"),
                      tmp / "file.txt" + " is not a run folder: it is not a folder");
    fs::create_directories(tmp / "half");
    write_text(tmp / "half/run.json", "{}");
    CHECK_THROWS_WITH(RunData(tmp / "half"),
                      tmp / "half" +
                          " is not a run folder: it has no series.csv and data.csv (a run "
                          "folder holds run.json, series.csv, data.csv, events.csv, log.txt "
                          "and config/)");
}

TEST_CASE("compare finds the first differing value", "[run_data]") {
    TempDir a("run_data_cmp_a"), b("run_data_cmp_b");
    const std::string ra = test::record_run(a / "run", 1), rb = test::record_run(b / "run", 1);
    Comparison same = compare(RunData(ra), RunData(rb));
    CHECK(same.identical);
    CHECK(same.rows == 34);
    CHECK(same.difference.empty());
    // one value changed in the last digit
    std::string text = read_text(rb + "/data.csv");
    const size_t row5 = [&] {
        size_t p = 0;
        for (int i = 0; i < 5; ++i)
            p = text.find('\n', p) + 1;
        return p;
    }();
    const size_t comma = text.find(',', row5);
    const size_t end = text.find(',', comma + 1);
    char& last = text[end - 1];
    last = last == '1' ? '2' : '1';
    write_text(rb + "/data.csv", text);
    Comparison diff = compare(RunData(ra), RunData(rb));
    CHECK_FALSE(diff.identical);
    CHECK_THAT(diff.difference,
               Catch::StartsWith("first difference at t = 0.12 s (data.csv line 6): snake.com.x "
                                 "is "));
}

namespace {

// run.json of `dir` with `from` replaced by `to` (which must be there)
void edit_meta(const std::string& dir, const std::string& from, const std::string& to) {
    std::string meta = read_text(dir + "/run.json");
    const size_t at = meta.find(from);
    REQUIRE(at != std::string::npos);
    meta.replace(at, from.size(), to);
    write_text(dir + "/run.json", meta);
}

// the line of run.json where `text` is
int line_of(const std::string& dir, const std::string& text) {
    const std::string meta = read_text(dir + "/run.json");
    const size_t at = meta.find(text);
    REQUIRE(at != std::string::npos);
    return 1 +
           static_cast<int>(std::count(meta.begin(), meta.begin() + static_cast<long>(at), '\n'));
}

}  // namespace

TEST_CASE("a run folder's files must be its own regular files", "[run_data]") {
    TempDir tmp("run_data_files");
    const std::string dir = test::record_run(tmp / "run", 0.1);
    const std::string data = read_text(dir + "/data.csv");
    // a FIFO with no writer: refused at once instead of waiting forever
    fs::remove(dir + "/data.csv");
    REQUIRE(::mkfifo((dir + "/data.csv").c_str(), 0600) == 0);
    CHECK_THROWS_WITH(RunData(dir), "cannot read " + dir +
                                        "/data.csv: not a regular file (a FIFO, device or socket)");
    // links could lead anywhere: /dev/zero (endless), a file outside the folder
    fs::remove(dir + "/data.csv");
    fs::create_symlink("/dev/zero", dir + "/data.csv");
    CHECK_THROWS_WITH(RunData(dir), "cannot read " + dir +
                                        "/data.csv: a symbolic link (the files of a run folder "
                                        "must be its own)");
    fs::remove(dir + "/data.csv");
    write_text(dir + "/data.csv", data);
    fs::rename(dir + "/series.csv", tmp / "elsewhere.csv");
    fs::create_symlink(tmp / "elsewhere.csv", dir + "/series.csv");
    CHECK_THROWS_WITH(RunData(dir), Catch::EndsWith("/series.csv: a symbolic link (the files "
                                                    "of a run folder must be its own)"));
    fs::remove(dir + "/series.csv");
    fs::rename(tmp / "elsewhere.csv", dir + "/series.csv");
    fs::rename(dir + "/run.json", tmp / "run.json");
    fs::create_symlink(tmp / "run.json", dir + "/run.json");
    CHECK_THROWS_WITH(RunData(dir), Catch::EndsWith("/run.json: a symbolic link (the files of "
                                                    "a run folder must be its own)"));
    fs::remove(dir + "/run.json");
    fs::create_directory(dir + "/run.json");
    CHECK_THROWS_WITH(RunData(dir), "cannot read " + dir + "/run.json: is a directory");
    fs::remove(dir + "/run.json");
    fs::rename(tmp / "run.json", dir + "/run.json");
    fs::create_symlink("/dev/zero", dir + "/events.csv.new");
    fs::rename(dir + "/events.csv.new", dir + "/events.csv");
    const RunData run(dir);
    CHECK_THROWS_WITH(run.events(), Catch::EndsWith("/events.csv: a symbolic link (the files of "
                                                    "a run folder must be its own)"));
    fs::remove(dir + "/log.txt");
    REQUIRE(::mkfifo((dir + "/log.txt").c_str(), 0600) == 0);
    CHECK_THROWS_WITH(run.log(), Catch::EndsWith("/log.txt: not a regular file (a FIFO, device "
                                                 "or socket)"));
}

TEST_CASE("oversized lines, too many series and huge headers are refused quickly", "[run_data]") {
    TempDir tmp("run_data_big");
    const std::string dir = test::record_run(tmp / "run", 0.1);
    const std::string data = read_text(dir + "/data.csv");
    const std::string header = data.substr(0, data.find('\n') + 1);
    // a line longer than 16 MiB (here without an end: /dev/zero-like content)
    write_text(dir + "/data.csv", header + std::string(kMaxLineBytes + 10, '1'));
    RunData cut(dir);
    CHECK_THROWS_WITH(cut.get("snake.com.x"),
                      dir + "/data.csv:2: line longer than the 16 MiB gaitlab reads");
    write_text(dir + "/data.csv", header + std::string(kMaxLineBytes + 10, '1') + "\n");
    CHECK_THROWS_WITH(RunData(dir).times(),
                      dir + "/data.csv:2: line longer than the 16 MiB gaitlab reads");
    // a million columns in the header
    std::string wide = "time";
    for (int i = 0; i < 1000000; ++i)
        wide += ",c";
    write_text(dir + "/data.csv", wide + "\n");
    CHECK_THROWS_WITH(RunData(dir),
                      dir +
                          "/data.csv:1: 81 columns expected (time and the 80 series of "
                          "series.csv), got 1000001");
    write_text(dir + "/data.csv", data);
    // more series than the reader takes
    std::string list = "name,kind,source,value,joint,body,unit\n";
    for (size_t i = 0; i <= kMaxSeries; ++i)
        list += "s" + std::to_string(i) + ",robot,snake,x,,,m\n";
    write_text(dir + "/series.csv", list);
    CHECK_THROWS_WITH(RunData(dir), dir +
                                        "/series.csv:100002: more than the 100000 series "
                                        "gaitlab reads");
}

TEST_CASE("run.json from elsewhere is checked value by value, with its line", "[run_data]") {
    TempDir tmp("run_data_meta");
    const std::string dir = test::record_run(tmp / "run", 0.1);
    const std::string meta = read_text(dir + "/run.json");
    const auto bad = [&](const std::string& from, const std::string& to, const std::string& what) {
        write_text(dir + "/run.json", meta);
        const int line = line_of(dir, from);
        edit_meta(dir, from, to);
        CHECK_THROWS_WITH(RunData(dir), dir + "/run.json:" + std::to_string(line) + ": " + what);
    };
    bad("\"dt\": 0.001", "\"dt\": -1", "simulation.dt: a positive number of seconds expected");
    bad("\"dt\": 0.001", "\"dt\": \"fast\"", "simulation.dt: a number expected");
    bad("\"dt\": 0.001", "\"dt\": 0", "simulation.dt: a positive number of seconds expected");
    bad("\"control_every\": 30", "\"control_every\": 0",
        "simulation.control_every: a whole number from 1 to 2147483647 expected");
    bad("\"control_every\": 30", "\"control_every\": 1e300",
        "simulation.control_every: a whole number from 1 to 2147483647 expected");
    // a bad solver, in front of the one the recorder wrote, is named
    bad("\"solver_iterations\": 20", "\"solver\": \"fast\", \"solver_iterations\": 20",
        "simulation.solver: 'pgs' or 'block_nncg' expected");
    bad("\"solver_iterations\": 20", "\"solver\": 1, \"solver_iterations\": 20",
        "simulation.solver: 'pgs' or 'block_nncg' expected");
    bad("\"solver_iterations\": 20", "\"solver\": null, \"solver_iterations\": 20",
        "simulation.solver: 'pgs' or 'block_nncg' expected");
    bad("\"first_tick\": 0", "\"first_tick\": -5",
        "first_tick: a whole number from 0 to 9000000000000000000 expected");
    bad("\"flush_seconds\": 2", "\"flush_seconds\": -1",
        "recording.flush_seconds: a non-negative number of seconds expected");
    bad("\"script\": \"\"", "\"script\": \"../../../etc/passwd\"",
        "run.script: a path inside config/ expected, got '../../../etc/passwd'");
    bad("\"script\": \"\"", "\"script\": \"/etc/passwd\"",
        "run.script: a path inside config/ expected, got '/etc/passwd'");
    bad("\"config\": []", "\"config\": [{\"role\": \"controller\", \"path\": \"a/../../x.lua\"}]",
        "config[].path: a path inside config/ expected, got 'a/../../x.lua'");
    // cut short anywhere: an error naming the file, never a crash
    for (size_t n = 0; n < meta.size(); n += 97) {
        write_text(dir + "/run.json", meta.substr(0, n));
        CHECK_THROWS_AS(RunData(dir), FormatError);
    }
    write_text(dir + "/run.json", meta);
    CHECK(RunData(dir).meta().options.dt == 0.001);
    // the solver is always written (block_nncg, the default); a folder recorded before it was,
    // when pgs was the default and went unwritten, reads as pgs
    CHECK(RunData(dir).meta().options.solver == ConstraintSolver::block_nncg);
    edit_meta(dir, "\"solver\": \"block_nncg\",", "");
    CHECK(RunData(dir).meta().options.solver == ConstraintSolver::pgs);
}

TEST_CASE("run folders written before the commit and the hashes were recorded still read",
          "[run_data]") {
    TempDir tmp("run_data_old");
    const std::string dir = tmp / "run";
    {
        Simulation sim(test::chain_world(2, Connection::pitch_pitch));
        RecordOptions o;
        o.dir = dir;
        RunContext c;
        c.files.push_back({"script", "a.lua", "/x/a.lua", "print(1)\n", "", 0, ""});
        Recorder rec(sim, o, c);
        sim.run(0.05);
        rec.close();
    }
    const std::string meta = read_text(dir + "/run.json");
    REQUIRE(meta.find("\"commit\": ") != std::string::npos);
    REQUIRE(meta.find("\"hash\": \"fnv1a64:") != std::string::npos);
    const RunMeta now = RunData(dir).meta();
    REQUIRE_FALSE(now.files.empty());
    CHECK(now.files[0].hash == "fnv1a64:c36adf2b03cacd3c");
    // run.json as gaitlab wrote it before: no commit, no hash, U+FFFD written as an escape
    std::string old = std::regex_replace(meta, std::regex(",\n *\"hash\": \"[^\"]*\""), "");
    old = std::regex_replace(old, std::regex("\n *\"commit\": \"[^\"]*\","), "");
    old = std::regex_replace(old, std::regex("\"args\": \\[\\]"), "\"args\": [\"\\ufffd\"]");
    REQUIRE(old.find("commit") == std::string::npos);
    REQUIRE(old.find("hash") == std::string::npos);
    REQUIRE(old.find("\\ufffd") != std::string::npos);
    write_text(dir + "/run.json", old);
    const RunData run(dir);
    CHECK(run.meta().status == "finished");
    CHECK(run.meta().options.dt == now.options.dt);
    CHECK(run.meta().args == std::vector<std::string>{"\xef\xbf\xbd"});
    REQUIRE(run.meta().files.size() == now.files.size());
    for (const ConfigFile& f : run.meta().files)
        CHECK(f.hash.empty());
    CHECK(run.meta().provenance.size() + 1 == now.provenance.size());
    for (const auto& [k, v] : run.meta().provenance)
        CHECK(k != "commit");
}

TEST_CASE("configuration files stay inside config/, links too", "[run_data]") {
    TempDir tmp("run_data_config");
    const std::string dir = test::record_run(tmp / "run", 0.1);
    const RunData run(dir);
    CHECK(run.config_file("controllers/a.lua") == dir + "/config/controllers/a.lua");
    CHECK(run.config_file("a/../b.lua") == dir + "/config/b.lua");
    for (const std::string p : {"../run.json", "/etc/passwd", "", ".", "a/../../x"}) {
        CHECK_THROWS_WITH(run.config_file(p),
                          dir + "/run.json: configuration file '" + p + "' is not inside config/");
    }
    fs::create_directories(dir + "/config/sub");
    fs::create_symlink("/etc", dir + "/config/sub/out");
    fs::create_symlink("/etc/passwd", dir + "/config/passwd.lua");
    CHECK_THROWS_WITH(run.config_file("sub/out/passwd"),
                      dir +
                          "/run.json: configuration file 'sub/out/passwd' leads out of "
                          "config/ (through a link)");
    CHECK_THROWS_WITH(run.config_file("passwd.lua"),
                      dir +
                          "/run.json: configuration file 'passwd.lua' leads out of config/ "
                          "(through a link)");
}

TEST_CASE("a folder left running says whether its process still runs", "[run_data]") {
    TempDir tmp("run_data_alive");
    const std::string dir = test::record_run(tmp / "run", 0.1);
    const RunProcess me = this_process();
    CHECK(me.pid == static_cast<long>(getpid()));
    CHECK(me.start_time > 0);
    CHECK(RunData(dir).meta().process.pid == me.pid);
    CHECK(RunData(dir).meta().process.start_time == me.start_time);
    CHECK(RunData(dir).state() == "finished");
    edit_meta(dir, "\"status\": \"finished\"", "\"status\": \"running\"");
    // this process still runs
    CHECK(liveness(me) == Liveness::alive);
    CHECK(RunData(dir).state() ==
          "running (still being written by process " + std::to_string(me.pid) + ")");
    // a process that ended
    const pid_t child = fork();
    if (child == 0) _exit(0);
    REQUIRE(waitpid(child, nullptr, 0) == child);
    RunProcess gone = me;
    gone.pid = child;
    CHECK(liveness(gone) == Liveness::gone);
    const std::string pid = "\"pid\": " + std::to_string(me.pid);
    edit_meta(dir, pid, "\"pid\": " + std::to_string(child));
    CHECK(RunData(dir).state() == "incomplete (the process ended without closing it)");
    edit_meta(dir, "\"pid\": " + std::to_string(child), pid);
    // the same pid, started at another time: another process (the pid was reused)
    RunProcess reused = me;
    reused.start_time = me.start_time + 1;
    CHECK(liveness(reused) == Liveness::gone);
    edit_meta(dir, "\"start_time\": " + std::to_string(me.start_time),
              "\"start_time\": " + std::to_string(me.start_time + 1));
    CHECK(RunData(dir).state() == "incomplete (the process ended without closing it)");
    // another boot: gone; another host: cannot be told from here
    RunProcess rebooted = me;
    rebooted.boot_id = "00000000-0000-0000-0000-000000000000";
    CHECK(liveness(rebooted) == Liveness::gone);
    RunProcess elsewhere = me;
    elsewhere.host = "elsewhere.example";
    CHECK(liveness(elsewhere) == Liveness::unknown);
    edit_meta(dir, "\"host\": \"" + me.host + "\"", "\"host\": \"elsewhere.example\"");
    CHECK(RunData(dir).state() == "running on elsewhere.example as process " +
                                      std::to_string(me.pid) +
                                      ", or ended there without closing it (it cannot be "
                                      "checked from here)");
    CHECK(liveness(RunProcess{}) == Liveness::unknown);
    edit_meta(dir, "\"status\": \"running\"",
              "\"status\": \"interrupted\",\n\"message\": \"SIGTERM\"");
    CHECK(RunData(dir).state() == "interrupted by SIGTERM");
}

TEST_CASE("series file names never leave the folder and never collide", "[run_data]") {
    const std::string long_name(300, 'x');
    const std::vector<std::string> names = {"snake.angle[1]",
                                            "../../etc/passwd",
                                            "/abs/path",
                                            "-rf",
                                            ".hidden",
                                            "..",
                                            "a\nb\x01",
                                            "a/b",
                                            "a_b",
                                            "a\\b",
                                            "",
                                            "\xff\xfe",
                                            "\xc3\xa9t\xc3\xa9",
                                            long_name};
    const std::vector<std::string> files = series_file_names(names);
    REQUIRE(files.size() == names.size());
    CHECK(files[0] == "snake.angle[1].csv");
    CHECK(files[1] == "_.._.._etc_passwd.csv");
    CHECK(files[2] == "_abs_path.csv");
    CHECK(files[3] == "_-rf.csv");
    CHECK(files[4] == "_.hidden.csv");
    CHECK(files[5] == "_...csv");
    CHECK(files[6] == "a_b_.csv");
    CHECK(files[7] == "a_b.csv");
    CHECK(files[8] == "a_b~2.csv");  // "a_b" itself, after "a/b" took its name
    CHECK(files[9] == "a_b~3.csv");
    CHECK(files[10] == "_.csv");
    CHECK(files[11] == "__.csv");
    CHECK(files[12] == "\xc3\xa9t\xc3\xa9.csv");
    CHECK(files[13] == std::string(240, 'x') + ".csv");
    const std::set<std::string> unique(files.begin(), files.end());
    CHECK(unique.size() == files.size());
    for (const std::string& f : files) {
        CHECK(f.find('/') == std::string::npos);
        CHECK(f.size() <= 255);
        CHECK(f[0] != '.');
        CHECK(f[0] != '-');
    }
}

TEST_CASE("a split export of hostile names writes inside its folder only", "[run_data]") {
    TempDir tmp("run_data_split");
    WorldSpec world = test::chain_world(2, Connection::pitch_pitch);
    world.robots[0].robot.name = "../../x";
    Simulation sim(world);
    RecordOptions o;
    o.dir = tmp / "run";
    o.series = {"robot"};
    {
        Recorder rec(sim, o);
        sim.run(0.1);
    }
    const RunData run(tmp / "run");
    const std::vector<std::string> files = run.write_split(tmp / "out/split", run.names());
    REQUIRE(files.size() == run.names().size());
    CHECK(files[0] == tmp / "out/split/_.._.._x.com.x.csv");
    // the folder holds the files and nothing else is made anywhere under out/
    size_t count = 0;
    for (const auto& e : fs::recursive_directory_iterator(tmp / "out")) {
        if (e.path() == fs::path(tmp / "out/split")) continue;
        CHECK(e.path().parent_path() == fs::path(tmp / "out/split"));
        ++count;
    }
    CHECK(count == files.size());
    CHECK_THAT(read_text(files[0]), Catch::StartsWith("time,../../x.com.x\n0,"));
    CHECK_THROWS_WITH(run.get("../../x.com.x", std::nan(""), 1),
                      "the time range must be numbers (got nan to 1)");
}

TEST_CASE("exports and plots never write over the run they read", "[run_data]") {
    // `gaitlab data RUN --csv RUN/data.csv` replaced the run's data with the export, and
    // `--plot RUN/data.png` did the same through the plot's data file beside the PNG
    TempDir tmp("run_data_own");
    const std::string dir = test::record_run(tmp / "run", 1);
    const RunData run(dir);
    const std::string data = read_text(tmp / "run/data.csv");
    fs::create_symlink(tmp / "run", tmp / "alias");
    for (const std::string& own :
         {tmp / "run/data.csv", tmp / "run/series.csv", tmp / "run/run.json",
          tmp / "run/events.csv", tmp / "run/log.txt", tmp / "run/config/anything.csv",
          tmp / "alias/data.csv", tmp / "run/../run/./series.csv"}) {
        INFO(own);
        CHECK_THROWS_WITH(run.write_csv(own, {"snake.com.x"}),
                          Catch::StartsWith("cannot write " + own + ": it is") &&
                              Catch::Contains("of the run " + dir + " being read"));
    }
    PlotOptions o;
    o.series = {"snake.com.x"};
    o.output = tmp / "run/data.png";
    CHECK_THROWS_WITH(plot(run, o), Catch::StartsWith("cannot write " + tmp / "run/data.csv"));
    CHECK_FALSE(fs::exists(tmp / "run/data.png"));
    // a series whose file name would be one of the run's: refused before the folder is made
    CHECK_THROWS_WITH(run.write_split(tmp / "run/config/split", {"snake.com.x"}),
                      Catch::Contains("in the config/ folder"));
    CHECK_FALSE(fs::exists(tmp / "run/config/split"));
    CHECK(read_text(tmp / "run/data.csv") == data);
    CHECK(RunData(dir).rows() == run.rows());
    // beside the run's files is fine
    run.write_csv(tmp / "run/com.csv", {"snake.com.x"});
    CHECK_THAT(read_text(tmp / "run/com.csv"), Catch::StartsWith("time,snake.com.x\n"));
}
