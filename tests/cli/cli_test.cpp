// The gaitlab executable (cli/main.cpp), run as users run it: exit status, stdout and the exact
// text on stderr. Failing runs print exactly one line, "gaitlab: FILE:LINE: message".
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gaitlab/run_data.h"

#include "temp_dir.h"

extern char** environ;

using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

const std::string kScripts = GAITLAB_SOURCE_DIR "/tests/cli/scripts";

struct Run {
    int status = -1;  // exit status, or -1 if the process did not exit normally
    std::string out;
    std::string err;
};

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// where the standard output of a command goes
enum class Out {
    file,         // captured (Run::out)
    full,         // /dev/full: every write fails with ENOSPC
    closed,       // no standard output at all (`>&-`)
    broken_pipe,  // a pipe whose reader has gone (`| head` after head exited)
};

// runs the gaitlab executable (`gaitlab ARGS...`) in directory `cwd`, capturing stdout and stderr.
// `gaitlab run` records by default: the tests record only where they say (--record DIR), so
// the source tree stays clean
Run cli(std::vector<std::string> args, const std::string& cwd = kScripts, Out out = Out::file) {
    if (!args.empty() && args[0] == "run" &&
        std::find(args.begin(), args.end(), "--record") == args.end()) {
        args.insert(args.begin() + 1, "--no-record");
    }
    char dir_template[] = "/tmp/gaitlab_cli_test.XXXXXX";
    const char* dir = mkdtemp(dir_template);
    REQUIRE(dir != nullptr);
    const std::string out_path = std::string(dir) + "/out", err_path = std::string(dir) + "/err";

    std::vector<std::string> argv_s{GAITLAB_BINARY};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : argv_s)
        argv.push_back(a.data());
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    int pipe_fds[2] = {-1, -1};
    switch (out) {
        case Out::file:
            posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(),
                                             O_WRONLY | O_CREAT | O_TRUNC, 0600);
            break;
        case Out::full:
            posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/full", O_WRONLY, 0);
            break;
        case Out::closed:
            posix_spawn_file_actions_addclose(&actions, STDOUT_FILENO);
            break;
        case Out::broken_pipe:
            REQUIRE(pipe(pipe_fds) == 0);
            close(pipe_fds[0]);  // the reader is gone before the first write
            posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
            posix_spawn_file_actions_addclose(&actions, pipe_fds[1]);
            break;
    }
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0600);
    // the child runs in `cwd`: posix_spawn has no chdir action before glibc 2.29's extension,
    // so change directory around the spawn
    char here[4096];
    REQUIRE(getcwd(here, sizeof here) != nullptr);
    REQUIRE(chdir(cwd.c_str()) == 0);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    REQUIRE(chdir(here) == 0);
    posix_spawn_file_actions_destroy(&actions);
    if (pipe_fds[1] >= 0) close(pipe_fds[1]);
    REQUIRE(rc == 0);

    int wstatus = 0;
    REQUIRE(waitpid(pid, &wstatus, 0) == pid);
    Run r;
    r.status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
    r.out = slurp(out_path);
    r.err = slurp(err_path);
    std::remove(out_path.c_str());
    std::remove(err_path.c_str());
    rmdir(dir);
    return r;
}

// a failed run: non-zero status, nothing on stdout, `line` (plus a newline) alone on stderr
void check_failure(const Run& r, const std::string& line) {
    INFO("stdout: " << r.out);
    CHECK(r.status > 0);
    CHECK(r.err == line + "\n");
    CHECK(r.err.find("terminate called") == std::string::npos);
    CHECK(r.err.find("stack traceback") == std::string::npos);
}

}  // namespace

TEST_CASE("the bare form runs a script like 'gaitlab run'", "[cli]") {
    // the README's command: a printed result, and one line saying where the run was recorded
    TempDir cwd("cli_bare");
    const Run r = cli({GAITLAB_SOURCE_DIR "/examples/first_snake.lua"}, cwd.str());
    CHECK(r.status == 0);
    CHECK_THAT(r.out, Catch::Matches(R"(moved [0-9.]+ m \(x -?[0-9.]+, y -?[0-9.]+\)\n)"));
    CHECK_THAT(r.err, Catch::Matches(R"(recorded runs/first_snake-[0-9]{8}-[0-9]{6}\n)"));
    const std::string dir = cwd / r.err.substr(9, r.err.size() - 10);
    CHECK(std::filesystem::exists(dir + "/data.csv"));
    // same simulation, same output
    const Run s = cli({"run", "examples/first_snake.lua"}, GAITLAB_SOURCE_DIR);
    CHECK(s.status == 0);
    CHECK(s.err.empty());
    CHECK(s.out == r.out);
}

TEST_CASE("a simulation file runs for its duration and says how far each robot moved", "[cli]") {
    const Run r = cli({"run", "examples/walk.xml"}, GAITLAB_SOURCE_DIR);
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK_THAT(r.out,
               Catch::Matches(R"(snake: moved 0\.[0-9]+ m \(x -[0-9.]+, y -?[0-9.]+\) in 20 s\n)"));
    const Run bare = cli({"examples/walk.xml"}, GAITLAB_SOURCE_DIR);
    CHECK(bare.out == r.out);
}

TEST_CASE("a bad simulation file fails with one line naming the file and line", "[cli]") {
    const std::string files = kScripts + "/files/";
    check_failure(cli({"run", "files/bad_actuation.xml"}),
                  "gaitlab: " + files +
                      "typo.xml:5: controller 'sine' has no parameter 'frequncy'; did you mean "
                      "'frequency'? (parameters: amplitude, frequency, phase, phase0, offset)");
    check_failure(cli({"run", "files/bad_floor.xml"}),
                  "gaitlab: " + files +
                      "slippery.xml:4: environment/floor[1]: floor friction must be in [0, 1] "
                      "(got -0.2)");
    check_failure(
        cli({"run", "files/none.xml"}),
        "gaitlab: " + files + "none.xml: cannot read the file: No such file or directory");
}

TEST_CASE("version and help options", "[cli]") {
    const Run v = cli({"--version"});
    CHECK(v.status == 0);
    CHECK_THAT(v.out, Catch::Matches(R"(gaitlab [0-9]+\.[0-9]+\.[0-9]+\n)"));
    CHECK(v.err.empty());

    const Run h = cli({"--help"});
    CHECK(h.status == 0);
    CHECK_THAT(h.out, Catch::Contains("Usage: gaitlab"));
    CHECK_THAT(h.out, Catch::Contains("run"));
    CHECK(h.err.empty());

    const Run rh = cli({"run", "--help"});
    CHECK(rh.status == 0);
    CHECK_THAT(rh.out, Catch::Contains("--seed"));
}

TEST_CASE("a missing script fails with one line naming it", "[cli]") {
    const Run r = cli({"run", "no_such_script.lua"});
    CHECK(r.status > 0);
    CHECK_THAT(r.err, Catch::StartsWith("gaitlab: cannot read no_such_script.lua"));
    CHECK(r.err.find('\n') == r.err.size() - 1);
    check_failure(r, r.err.substr(0, r.err.size() - 1));

    const Run b = cli({"no_such_script.lua"});
    CHECK(b.status == r.status);
    CHECK(b.err == r.err);

    // the console does not open on a script it cannot read
    const Run i = cli({"-i", "no_such_script.lua"});
    CHECK(i.status == 1);
    CHECK(i.out.empty());
    CHECK(i.err == "gaitlab: cannot read no_such_script.lua: No such file or directory\n");

    check_failure(cli({"run", "notes.txt"}),
                  "gaitlab: notes.txt: expected a Lua script (FILE.lua) or a simulation file "
                  "(FILE.xml)");
}

TEST_CASE("script errors print one line: gaitlab: FILE:LINE: message", "[cli]") {
    check_failure(cli({"run", "syntax_error.lua"}),
                  "gaitlab: syntax_error.lua:3: '}' expected near 'end'");
    check_failure(cli({"run", "runtime_error.lua"}),
                  "gaitlab: runtime_error.lua:4: attempt to call a nil value (field 'populate')");
    check_failure(cli({"run", "unknown_key.lua"}),
                  "gaitlab: unknown_key.lua:2: bad argument #1 to 'chain' (unknown key "
                  "'conection'; did you mean 'connection'?)");
    check_failure(cli({"run", "out_of_range.lua"}),
                  "gaitlab: out_of_range.lua:7: sine.amplitude must be in [0, 90] deg (got 120)");
    check_failure(cli({"run", "bad_sensor.lua"}),
                  "gaitlab: bad_sensor.lua:3: bad argument #1 to 'sensor' (robot 'snake' has no "
                  "module 9 (it has modules 1 to 8))");
    // the file is named as the user gave it
    check_failure(cli({"run", kScripts + "/runtime_error.lua"}, "/"),
                  "gaitlab: " + kScripts +
                      "/runtime_error.lua:4: attempt to call a nil value (field 'populate')");
    check_failure(cli({"scripts/unknown_key.lua"}, GAITLAB_SOURCE_DIR "/tests/cli"),
                  "gaitlab: scripts/unknown_key.lua:2: bad argument #1 to 'chain' (unknown key "
                  "'conection'; did you mean 'connection'?)");
}

TEST_CASE("a controller error names the controller file and line", "[cli]") {
    const std::string message =
        "controllers/bad_step.lua:5: attempt to perform arithmetic on a nil value (field 'gain')";
    check_failure(cli({"run", "controller_error.lua"}), "gaitlab: " + message);
    // controller paths resolve against the folder of the script that loads them
    check_failure(cli({"run", "scripts/controller_error.lua"}, GAITLAB_SOURCE_DIR "/tests/cli"),
                  "gaitlab: scripts/" + message);
}

TEST_CASE("scripts get their arguments in arg", "[cli]") {
    const Run r = cli({"args.lua", "one", "two words", "-4"});
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK(r.out == "args.lua\n1\tone\n2\ttwo words\n3\t-4\n");

    const Run none = cli({"run", "args.lua"});
    CHECK(none.out == "args.lua\n");

    // gaitlab's own options may stand anywhere; the script's come after FILE
    const Run seeded = cli({"run", "args.lua", "--seed", "3", "x"});
    CHECK(seeded.status == 0);
    CHECK(seeded.out == "args.lua\n1\tx\n");
    const Run after = cli({"run", "args.lua", "x", "--seed", "3"});
    CHECK(after.out == "args.lua\n1\tx\n");
    // after "--" everything is the script's, options and "--" too
    const Run dashed = cli({"run", "args.lua", "x", "--", "--foo", "1", "--seed", "--", "-4"});
    CHECK(dashed.status == 0);
    CHECK(dashed.err.empty());
    CHECK(dashed.out == "args.lua\n1\tx\n2\t--foo\n3\t1\n4\t--seed\n5\t--\n6\t-4\n");
    const Run bare = cli({"args.lua", "--", "--three"});
    CHECK(bare.out == "args.lua\n1\t--three\n");
    const Run file_after = cli({"run", "--", "args.lua", "--x"});
    CHECK(file_after.out == "args.lua\n1\t--x\n");
}

TEST_CASE("an option gaitlab does not know is an error wherever it stands", "[cli]") {
    check_failure(cli({"run", "--no-recrod", "args.lua"}),
                  "gaitlab: unknown option '--no-recrod' for 'gaitlab run'; did you mean "
                  "'--no-record'? (see 'gaitlab run --help')");
    // after FILE too: it no longer goes to the script unnoticed
    check_failure(cli({"run", "args.lua", "--sed", "3"}),
                  "gaitlab: unknown option '--sed' for 'gaitlab run'; did you mean '--seed'? "
                  "(see 'gaitlab run --help')");
    check_failure(cli({"args.lua", "one", "--foo"}),
                  "gaitlab: unknown option '--foo' for 'gaitlab run' (the script's arguments "
                  "go after FILE, and after '--' when one starts with '-'; see 'gaitlab run "
                  "--help')");
    check_failure(cli({"run", "args.lua", "x", "--no-recod=1"}),
                  "gaitlab: unknown option '--no-recod' for 'gaitlab run'; did you mean "
                  "'--no-record'? (see 'gaitlab run --help')");
    check_failure(cli({"data", "somewhere", "--lsit"}),
                  "gaitlab: unknown option '--lsit' for 'gaitlab data'; did you mean '--list'? "
                  "(see 'gaitlab data --help')");
    check_failure(cli({"data", "--evnts=1", "somewhere"}),
                  "gaitlab: unknown option '--evnts' for 'gaitlab data'; did you mean "
                  "'--events'? (see 'gaitlab data --help')");
    check_failure(cli({"data", "somewhere", "other"}),
                  "gaitlab: unexpected argument 'other' for 'gaitlab data' (see 'gaitlab data "
                  "--help')");
    check_failure(cli({"replay", "somewhere", "--int", "x"}),
                  "gaitlab: unknown option '--int' for 'gaitlab replay'; did you mean '--into'? "
                  "(see 'gaitlab replay --help')");
    check_failure(cli({"--verison"}),
                  "gaitlab: unknown option '--verison'; did you mean '--version'? (see 'gaitlab "
                  "--help')");
    check_failure(cli({"dtaa", "x"}),
                  "gaitlab: unknown command 'dtaa'; did you mean 'data'? (see 'gaitlab --help')");
    // nothing ran: no output, no run folder
    TempDir tmp("cli_unknown");
    const Run r = cli({"run", "--record", tmp / "run", "args.lua", "--fast"});
    CHECK(r.status == 2);
    CHECK(r.out.empty());
    CHECK_FALSE(std::filesystem::exists(tmp / "run"));
}

TEST_CASE("numeric options take numbers in their range, nothing else", "[cli]") {
    for (const std::string seed : {"-1", "99999999999999999999999", "18446744073709551616", "1.5",
                                   "0x10", "", "nan", "3 "}) {
        check_failure(cli({"run", "--seed", seed, "random.lua"}),
                      "gaitlab: --seed: a whole number from 0 to 18446744073709551615 expected "
                      "(got '" +
                          seed + "') (see 'gaitlab run --help')");
    }
    const Run max = cli({"run", "--seed", "18446744073709551615", "random.lua"});
    CHECK(max.status == 0);
    CHECK(max.err.empty());
    for (const std::string t : {"nan", "-nan", "inf", "-inf", "1x", "", "1e999", "0x1p3"}) {
        check_failure(cli({"data", "somewhere", "--from", t}),
                      "gaitlab: --from: a number of seconds expected (got '" + t + "')");
        check_failure(cli({"data", "somewhere", "--to", t}),
                      "gaitlab: --to: a number of seconds expected (got '" + t + "')");
    }
    check_failure(cli({"data", "somewhere", "--from", "5", "--to", "1"}),
                  "gaitlab: --from 5 is after --to 1: no row can be in between");
}

TEST_CASE("the seed option makes math.random reproducible", "[cli]") {
    const Run a = cli({"run", "--seed", "11", "random.lua"});
    const Run b = cli({"run", "--seed", "11", "random.lua"});
    const Run c = cli({"run", "--seed", "12", "random.lua"});
    const Run d = cli({"run", "random.lua", "--seed", "12"});
    const Run e = cli({"random.lua"});
    const Run f = cli({"run", "--seed", "0", "random.lua"});
    CHECK(a.status == 0);
    CHECK(a.err.empty());
    CHECK_THAT(a.out, Catch::Matches(R"([0-9]+ [0-9]+ [0-9]+ [0-9]+\n)"));
    CHECK(a.out == b.out);
    CHECK(a.out != c.out);
    CHECK(c.out == d.out);
    // no --seed means seed 0: runs are reproducible by default
    CHECK(e.out == f.out);
    CHECK(e.out != a.out);

    // command-line mistakes are one line too
    check_failure(cli({"run", "--seed", "many", "random.lua"}),
                  "gaitlab: --seed: a whole number from 0 to 18446744073709551615 expected (got "
                  "'many') (see 'gaitlab run --help')");
    check_failure(cli({"run"}),
                  "gaitlab: a script or simulation file is required (gaitlab run FILE.lua; an "
                  "option before it takes its value first) (see 'gaitlab run --help')");
    check_failure(cli({"run", ""}),
                  "gaitlab: a script or simulation file expected, got an "
                  "empty name (see 'gaitlab run --help')");
    // an empty name after -i opened a plain console, as if none had been given
    check_failure(cli({"-i", ""}),
                  "gaitlab: a Lua file to run first expected, got an empty "
                  "name (see 'gaitlab console --help')");
    check_failure(cli({"launch"}), "gaitlab: unknown command 'launch' (see 'gaitlab --help')");
}

// ---------------------------------------------------------------------------------------------
// recording, gaitlab data, gaitlab replay

namespace {

const std::string kFirstSnake = GAITLAB_SOURCE_DIR "/examples/first_snake.lua";

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// starts gaitlab with `args` (argv[0] included) in the background, stderr to `err`
pid_t spawn(const std::vector<std::string>& args, const std::string& err) {
    std::vector<std::string> argv_s = args;
    std::vector<char*> argv;
    for (std::string& a : argv_s)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0600);
    pid_t pid = 0;
    const int rc = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    REQUIRE(rc == 0);
    return pid;
}

// the last complete number line of a progress file, or -1
double last_progress(const std::string& path) {
    const std::string text = slurp(path);
    const size_t end = text.rfind('\n');
    if (end == std::string::npos) return -1;
    const size_t start = text.rfind('\n', end - 1);
    return std::atof(text.substr(start == std::string::npos ? 0 : start + 1).c_str());
}

}  // namespace

TEST_CASE("gaitlab run records into --record DIR, or nothing with --no-record", "[cli][data]") {
    TempDir tmp("cli_record");
    const Run r = cli({"run", "--record", tmp / "run", kFirstSnake}, tmp.str());
    CHECK(r.status == 0);
    CHECK(r.err == "recorded " + (tmp / "run") + "\n");
    const gaitlab::RunData run(tmp / "run");
    CHECK(run.meta().status == "finished");
    CHECK(run.rows() == 667);
    CHECK(slurp(tmp / "run/config/first_snake.lua") == slurp(kFirstSnake));
    CHECK_THAT(run.log(), Catch::Contains("\nmoved 0.569 m"));
    bool command = false;
    for (const auto& [k, v] : run.meta().provenance)
        command = command || (k == "command" && v.find("--record") != std::string::npos);
    CHECK(command);

    const Run n = cli({"run", "--no-record", kFirstSnake}, tmp.str());
    CHECK(n.err.empty());
    CHECK(n.out == r.out);
    CHECK_FALSE(std::filesystem::exists(tmp / "runs"));
    check_failure(cli({"run", "--record", tmp / "x", "--no-record", kFirstSnake}),
                  "gaitlab: --record excludes --no-record (see 'gaitlab run --help')");
    // an option given twice says so, and the help meant is the subcommand's (CLI11 said "At
    // Most 1 required but received 2 (see 'gaitlab --help')")
    check_failure(cli({"run", "--seed", "1", "--seed", "2", "x.lua"}),
                  "gaitlab: --seed given 2 times (give it once) (see 'gaitlab run --help')");
    check_failure(cli({"make", "robot"}),
                  "gaitlab: --output is required (see 'gaitlab make robot --help')");

    // a folder that cannot be made: one line naming it, exit 1
    std::ofstream(tmp / "file") << "x";
    check_failure(cli({"run", "--record", tmp / "file/run", kFirstSnake}, tmp.str()),
                  "gaitlab: " + kFirstSnake + ":6: cannot create run folder " + (tmp / "file/run") +
                      ": Not a directory");
    // a run that fails keeps its folder, marked failed with the reason
    const Run f = cli({"run", "--record", tmp / "failed", "controller_error.lua"});
    CHECK(f.status == 1);
    const gaitlab::RunData failed(tmp / "failed");
    CHECK(failed.meta().status == "failed");
    CHECK_THAT(failed.meta().message,
               Catch::Contains("controllers/bad_step.lua:5: attempt to perform arithmetic"));
    CHECK(slurp(tmp / "failed/config/controllers/bad_step.lua") ==
          slurp(kScripts + "/controllers/bad_step.lua"));
    // its replay fails the same way, at the same time: identical, exit status 0
    const Run same = cli({"replay", tmp / "failed"});
    CHECK(same.status == 0);
    CHECK(same.err.empty());
    CHECK_THAT(same.out, Catch::StartsWith("replay identical: ") &&
                             Catch::Contains(" series, bit for bit (the run failed the same way "
                                             "at t = 0 s: controllers/bad_step.lua:5: attempt to "
                                             "perform arithmetic"));
    // a replay that fails otherwise differs, with both errors
    std::string meta = slurp(tmp / "failed/run.json");
    meta.replace(meta.find("(field 'gain')"), 14, "(field 'gains')");
    std::ofstream(tmp / "failed/run.json") << meta;
    const Run other = cli({"replay", tmp / "failed", "--into", tmp / "other"});
    CHECK(other.status == 1);
    CHECK_THAT(other.err, Catch::StartsWith("gaitlab: replay differs: the run failed at t = 0 s "
                                            "with: controllers/bad_step.lua:5: ") &&
                              Catch::Contains("(field 'gains'); the replay at t = 0 s with: "));
}

TEST_CASE("each simulation of a script gets its own run folder", "[cli][data]") {
    TempDir tmp("cli_two");
    const Run r = cli({"run", "--record", tmp / "run", "two_sims.lua"});
    CHECK(r.status == 0);
    CHECK(r.err == "recorded 2 runs: " + (tmp / "run") + ", " + (tmp / "run-2") + "\n");
    CHECK(gaitlab::RunData(tmp / "run").meta().simulation == 1);
    CHECK(gaitlab::RunData(tmp / "run-2").meta().simulation == 2);
    CHECK(gaitlab::RunData(tmp / "run-2").series()[0].name == "worm3.com.x");
    // replaying the second one reruns the script and records only its second simulation
    const Run p = cli({"replay", tmp / "run-2"});
    CHECK(p.status == 0);
    CHECK_THAT(p.out, Catch::StartsWith("replay identical: 4 rows x "));
    CHECK_FALSE(std::filesystem::exists(tmp / "run-2-replay-2"));
}

TEST_CASE("os.exit closes the run folders first", "[cli][data]") {
    TempDir tmp("cli_exit");
    const Run ok = cli({"run", "--record", tmp / "ok", "exits.lua"});
    CHECK(ok.status == 0);
    CHECK(ok.out == "leaving\n");
    const gaitlab::RunData a(tmp / "ok");
    CHECK(a.meta().status == "finished");
    CHECK(a.rows() == 34);  // all of it, though the flush period is a minute
    CHECK_THAT(a.log(), Catch::Contains("\nleaving\n"));
    const Run bad = cli({"run", "--record", tmp / "bad", "exits.lua", "4"});
    CHECK(bad.status == 4);
    const gaitlab::RunData b(tmp / "bad");
    CHECK(b.meta().status == "failed");
    CHECK(b.meta().message == "the script called os.exit with a failure status");
}

TEST_CASE("gaitlab data lists, extracts, exports and plots series", "[cli][data]") {
    TempDir tmp("cli_data");
    REQUIRE(cli({"run", "--record", tmp / "run", kFirstSnake}, tmp.str()).status == 0);
    const std::string dir = tmp / "run";

    const Run summary = cli({"data", dir});
    CHECK(summary.status == 0);
    CHECK_THAT(summary.out, Catch::Contains("status   finished\n"));
    CHECK_THAT(summary.out, Catch::Contains("rows     667, t = 0 .. 19.98 s, every 30 ticks"));
    // the gaitlab that recorded it, with the commit it was built from
    CHECK_THAT(
        summary.out,
        Catch::Matches(R"((.|\n)*\ngaitlab  [0-9]+\.[0-9]+\.[0-9]+ \(commit [^)\n]+\)\n(.|\n)*)"));
    {
        // a folder from before gaitlab kept the commit shows the version alone
        const std::string meta = slurp(dir + "/run.json");
        const size_t at = meta.find("\n    \"commit\": ");
        REQUIRE(at != std::string::npos);
        const size_t end = meta.find('\n', at + 1);
        write_text(dir + "/run.json", meta.substr(0, at) + meta.substr(end));
        const Run old = cli({"data", dir});
        CHECK(old.status == 0);
        CHECK_THAT(old.out, Catch::Matches(R"((.|\n)*\ngaitlab  [0-9]+\.[0-9]+\.[0-9]+\n(.|\n)*)"));
        write_text(dir + "/run.json", meta);
    }

    const Run list = cli({"data", dir, "--list"});
    CHECK(list.status == 0);
    CHECK_THAT(list.out, Catch::StartsWith("name "));
    CHECK_THAT(list.out, Catch::Matches(R"((.|\n)*\nsnake\.angle\[3\] +robot +3 +deg\n(.|\n)*)"));
    CHECK_THAT(list.out, Catch::Matches(R"((.|\n)*\nsine\.amplitude +controller +deg\n(.|\n)*)"));

    const Run one = cli({"data", dir, "--series", "sine.amplitude,sine.angle[2]", "--to", "0.06"});
    CHECK(one.status == 0);
    CHECK_THAT(one.out,
               Catch::Matches("time,sine.amplitude,sine.angle\\[2\\]\n0,40,0\n0.03,40,[-0-9.e]+\n"
                              "0.06,40,[-0-9.e]+\n"));

    REQUIRE(cli({"data", dir, "--series", "snake.com.x", "--csv", tmp / "x.csv"}).status == 0);
    CHECK(slurp(tmp / "x.csv").rfind("time,snake.com.x\n0,0.288", 0) == 0);
    const Run split = cli({"data", dir, "--series", "snake.angle[*]", "--split", tmp / "each"});
    CHECK(split.status == 0);
    for (int j = 1; j <= 8; ++j)
        CHECK(std::filesystem::exists(tmp / ("each/snake.angle[" + std::to_string(j) + "].csv")));

    const Run plot =
        cli({"data", dir, "--plot", tmp / "p.png", "--series", "snake.com.x,snake.com.y"});
    CHECK(plot.status == 0);
    CHECK(plot.out == "wrote " + (tmp / "p.png") + " (gnuplot script " + (tmp / "p.gp") +
                          ", data " + (tmp / "p.csv") + ")\n");
    CHECK(std::filesystem::file_size(tmp / "p.png") > 5000);

    check_failure(cli({"data", dir, "--series", "snake.angle[12]"}),
                  "gaitlab: unknown series 'snake.angle[12]'; did you mean 'snake.angle[1]', "
                  "'snake.angle[2]' or 'snake.angle[3]'?");
    check_failure(cli({"data", tmp.str()}),
                  "gaitlab: " + tmp.str() +
                      " is not a run folder: it has no run.json, series.csv and data.csv (a "
                      "run folder holds run.json, series.csv, data.csv, events.csv, log.txt and "
                      "config/)");
    check_failure(cli({"data", dir, "--plot", tmp / "q.png"}),
                  "gaitlab: --plot needs --series NAME[,NAME...] or --xy X Y");

    // the path seen from above, over a time range
    const Run path = cli({"data", dir, "--plot", tmp / "xy/path.png", "--xy", "snake.com.x",
                          "snake.com.y", "--from", "1", "--to", "2"});
    CHECK(path.status == 0);
    CHECK(path.out == "wrote " + (tmp / "xy/path.png") + " (gnuplot script " +
                          (tmp / "xy/path.gp") + ", data " + (tmp / "xy/path.csv") + ")\n");
    CHECK(std::filesystem::file_size(tmp / "xy/path.png") > 5000);
    const std::string xy = slurp(tmp / "xy/path.csv");
    CHECK(xy.rfind("time,snake.com.x,snake.com.y\n1.02,", 0) == 0);
    CHECK(std::count(xy.begin(), xy.end(), '\n') == 1 + 33);  // 1.02 .. 1.98 s, every 0.03 s
    CHECK_THAT(slurp(tmp / "xy/path.gp"), Catch::Contains("set size ratio -1"));
    check_failure(cli({"data", dir, "--plot", tmp / "q.png", "--xy", "snake.com.x", "snake.com.y",
                       "--series", "snake.com.z"}),
                  "gaitlab: --xy plots one series against another: give no --series with it");
    check_failure(cli({"data", dir, "--xy", "snake.com.x", "snake.com.y"}),
                  "gaitlab: --xy needs --plot OUT.png");
    check_failure(cli({"data", dir, "--plot", tmp / "q.png", "--xy", "snake.com.x", "snake.cm.y"}),
                  "gaitlab: unknown series 'snake.cm.y'; did you mean 'snake.com.y', "
                  "'snake.com.x' or 'snake.com.z'?");
    check_failure(cli({"data", dir, "--plot", tmp / "q.png", "--xy", "robot", "snake.com.y"}),
                  "gaitlab: the x axis takes one series; 'robot' selects 119 (snake.com.x, "
                  "snake.com.y, snake.com.z, snake.com.vx, snake.com.vy, ...)");
    check_failure(cli({"data", dir, "--plot", tmp / "q.png", "--xy", "snake.com.x", "snake.com.y",
                       "--from", "50"}),
                  "gaitlab: nothing to plot: the run has no rows from 50 s on");
    check_failure(cli({"data", dir, "--plot", tmp / "q.png", "--xy", "", "snake.com.y"}),
                  "gaitlab: --xy: two series names expected (X and Y)");
    const Run one_name = cli({"data", dir, "--plot", tmp / "q.png", "--xy", "snake.com.x"});
    CHECK(one_name.status > 0);
    CHECK_THAT(one_name.err, Catch::StartsWith("gaitlab: --xy: "));
    CHECK_FALSE(std::filesystem::exists(tmp / "q.png"));
}

TEST_CASE("gaitlab replay reproduces a run bit for bit and says when it does not",
          "[cli][replay]") {
    TempDir tmp("cli_replay");
    const std::string script = GAITLAB_SOURCE_DIR "/examples/my_sine_snake.lua";
    REQUIRE(cli({"run", "--record", tmp / "run", script}, tmp.str()).status == 0);
    const Run r = cli({"replay", tmp / "run"});
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK(r.out ==
          "replay identical: 667 rows x 138 series, bit for bit; 0 recorded changes "
          "applied (into " +
              (tmp / "run-replay") + ")\n");
    // a controller that is not the one that ran gives other data
    std::string code = slurp(tmp / "run/config/controllers/my_sine.lua");
    code.replace(code.find("2 * math.pi"), 11, "2.001 * math.pi");
    std::ofstream(tmp / "run/config/controllers/my_sine.lua") << code;
    const Run d = cli({"replay", tmp / "run", "--into", tmp / "other"});
    CHECK(d.status == 1);
    CHECK_THAT(d.err, Catch::StartsWith("gaitlab: replay differs: first difference at t = 0.03 "
                                        "s (data.csv line 3): "));
    check_failure(cli({"replay", tmp / "nothing"}),
                  "gaitlab: no run folder at " + (tmp / "nothing"));
}

TEST_CASE("a run on a compliant floor replays bit for bit, a bad value in its copy is named",
          "[cli][replay]") {
    TempDir tmp("cli_replay_soft");
    namespace fs = std::filesystem;
    fs::copy(GAITLAB_SOURCE_DIR "/examples/walk", tmp / "walk", fs::copy_options::recursive);
    fs::copy(GAITLAB_SOURCE_DIR "/examples/controllers", tmp / "controllers",
             fs::copy_options::recursive);
    const std::string environment =
        "<?xml version=\"1.0\"?>\n"
        "<gaitlab version=\"1\">\n"
        "    <environment>\n"
        "        <floor friction=\"0.8\" FLOOR/>\n"
        "        <place robot=\"snake\" position=\"0 0 0\"/>\n"
        "    </environment>\n"
        "</gaitlab>\n";
    auto floor = [&](const std::string& attrs) {
        std::string text = environment;
        text.replace(text.find("FLOOR"), 5, attrs);
        return text;
    };
    write_text(tmp / "walk/flat.environment.xml", floor("stiffness=\"1e4\" damping=\"20\""));
    write_text(tmp / "walk/rigid.environment.xml", floor("rigid=\"true\""));
    const std::string sim = slurp(GAITLAB_SOURCE_DIR "/examples/walk.xml");
    std::string rigid_sim = sim;
    rigid_sim.replace(rigid_sim.find("flat.environment"), 16, "rigid.environment");
    write_text(tmp / "soft.xml", sim);
    write_text(tmp / "rigid.xml", rigid_sim);
    for (const char* name : {"soft", "rigid"}) {
        REQUIRE(cli({"run", "--record", tmp / name, (tmp / name) + ".xml"}, tmp.str()).status == 0);
    }
    // the run's copy of the environment holds the floor's values, and they made a difference
    CHECK_THAT(slurp(tmp / "soft/config/walk/flat.environment.xml"),
               Catch::Contains("stiffness=\"1e4\" damping=\"20\""));
    CHECK(slurp(tmp / "soft/data.csv") != slurp(tmp / "rigid/data.csv"));
    const Run r = cli({"replay", tmp / "soft"});
    CHECK(r.status == 0);
    CHECK_THAT(r.out, Catch::StartsWith("replay identical: "));
    CHECK_THAT(r.out, Catch::Contains("bit for bit"));
    // a bad value in the recording's copy: its file, line and what is expected
    write_text(tmp / "soft/config/walk/flat.environment.xml",
               floor("stiffness=\"-1e4\" damping=\"20\""));
    check_failure(cli({"replay", tmp / "soft", "--into", tmp / "other"}),
                  "gaitlab: replay failed: " + (tmp / "soft/config/walk/flat.environment.xml") +
                      ":4: environment/floor[1]: floor stiffness must be positive (got -10000 "
                      "N/m)");
    write_text(tmp / "soft/config/walk/flat.environment.xml",
               floor("rigid=\"true\" stiffness=\"1e4\""));
    check_failure(cli({"replay", tmp / "soft", "--into", tmp / "other"}),
                  "gaitlab: replay failed: " + (tmp / "soft/config/walk/flat.environment.xml") +
                      ":4: environment/floor[1]: a rigid floor takes no stiffness (a floor is "
                      "rigid, or compliant with a stiffness and a damping)");
}

TEST_CASE("a run of the block_nncg solver replays with it, and not with pgs", "[cli][replay]") {
    TempDir tmp("cli_replay_solver");
    write_text(tmp / "pyroll.lua",
               "local robot = gaitlab.robot.chain{ name = 'snake', modules = 4, connection = "
               "'pitch-yaw' }\n"
               "local world = gaitlab.world{ floor = { friction = 1.0 } }\n"
               "world:add(robot)\n"
               "robot:group('pitch'):drive(gaitlab.controllers.sine{ amplitude = 40, frequency "
               "= 0.5 })\n"
               "robot:group('yaw'):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = "
               "0.5, phase0 = 90 })\n"
               "local sim = gaitlab.simulation{ world = world, solver = 'block_nncg' }\n"
               "sim:run(2)\n");
    REQUIRE(cli({"run", "--record", tmp / "run", tmp / "pyroll.lua"}, tmp.str()).status == 0);
    CHECK(gaitlab::RunData(tmp / "run").meta().options.solver ==
          gaitlab::ConstraintSolver::block_nncg);
    const Run r = cli({"replay", tmp / "run"});
    CHECK(r.status == 0);
    CHECK_THAT(r.out, Catch::StartsWith("replay identical: "));
    CHECK_THAT(r.out, Catch::Contains("bit for bit"));
    // the same run said to be solved by pgs: the script's simulation no longer matches it
    const std::string meta = slurp(tmp / "run/run.json");
    const size_t at = meta.find("\"block_nncg\"");
    REQUIRE(at != std::string::npos);
    write_text(tmp / "run/run.json", meta.substr(0, at) + "\"pgs\"" + meta.substr(at + 12));
    const Run d = cli({"replay", tmp / "run", "--into", tmp / "other"});
    CHECK(d.status == 1);
    CHECK_THAT(d.err, Catch::StartsWith(
                          "gaitlab: replay differs: the replayed simulation has other options "
                          "than the run: solver block_nncg here, pgs in the run"));
}

TEST_CASE(
    "a run of a long pitch-yaw chain made without Newton steps does not replay with them, and "
    "the message says what to give",
    "[cli][replay]") {
    TempDir tmp("cli_replay_newton");
    write_text(tmp / "long.lua",
               "local robot = gaitlab.robot.chain{ name = 'snake', modules = 14, connection = "
               "'pitch-yaw' }\n"
               "local world = gaitlab.world()\n"
               "world:add(robot)\n"
               "robot:group('pitch'):drive(gaitlab.controllers.sine{ amplitude = 40 })\n"
               "local sim = gaitlab.simulation{ world = world }\n"
               "sim:run(0.2)\n");
    REQUIRE(cli({"run", "--record", tmp / "run", tmp / "long.lua"}, tmp.str()).status == 0);
    CHECK(gaitlab::RunData(tmp / "run").meta().options.newton_steps ==
          gaitlab::kLongChainNewtonSteps);
    CHECK(cli({"replay", tmp / "run"}).status == 0);
    // the run as one made before such a chain got the Newton steps by default: none recorded
    const std::string meta = slurp(tmp / "run/run.json");
    const size_t at = meta.find("\"newton_steps\"");
    REQUIRE(at != std::string::npos);
    const size_t end = meta.find_first_of(",}", at);
    std::string old = meta.substr(0, at) + meta.substr(end + (meta[end] == ',' ? 1 : 0));
    write_text(tmp / "run/run.json", old);
    REQUIRE(gaitlab::RunData(tmp / "run").meta().options.newton_steps == 0);
    const Run d = cli({"replay", tmp / "run", "--into", tmp / "other"});
    CHECK(d.status == 1);
    CHECK_THAT(d.err, Catch::StartsWith("gaitlab: replay differs: the replayed simulation has "
                                        "other options than the run: newton_steps 8 here, 0 in "
                                        "the run (a pitch-yaw chain of 13 modules or more gets 8 "
                                        "when newton_steps is not given, since 2026-11-30; runs "
                                        "recorded before got 0, then 4: give newton_steps = 0 to "
                                        "replay this run)"));
    // and as one made while such a chain got 4 by default
    std::string four = meta;
    four.replace(at, end - at, "\"newton_steps\": 4");
    write_text(tmp / "run/run.json", four);
    REQUIRE(gaitlab::RunData(tmp / "run").meta().options.newton_steps == 4);
    const Run e = cli({"replay", tmp / "run", "--into", tmp / "another"});
    CHECK(e.status == 1);
    CHECK_THAT(e.err, Catch::Contains("newton_steps 8 here, 4 in the run (") &&
                          Catch::Contains("give newton_steps = 4 to replay this run)"));
}

TEST_CASE("a run killed with SIGKILL leaves a readable folder missing at most one flush period",
          "[cli][data]") {
    TempDir tmp("cli_kill");
    const std::string progress = tmp / "progress";
    const pid_t pid = spawn(
        {GAITLAB_BINARY, "run", "--record", tmp / "run", kScripts + "/long_run.lua"}, progress);
    // (wall time, simulated time) as the run reports it
    std::vector<std::pair<double, double>> seen;
    const double start = now_seconds();
    while (now_seconds() - start < 1.5) {
        const double t = last_progress(progress);
        if (t > 0) seen.emplace_back(now_seconds(), t);
        usleep(10000);
    }
    const double killed_at = now_seconds();
    REQUIRE(kill(pid, SIGKILL) == 0);
    int wstatus = 0;
    REQUIRE(waitpid(pid, &wstatus, 0) == pid);
    CHECK(WIFSIGNALED(wstatus));
    const double sim_at_kill = last_progress(progress);
    REQUIRE(sim_at_kill > 1);

    const gaitlab::RunData run(tmp / "run");
    CHECK(run.meta().status == "running");
    const std::vector<double> t = run.times();
    REQUIRE(!t.empty());
    const double last = t.back();
    // the data reaches what the run had done one flush period (0.2 s) before the kill, with
    // 0.3 s more for the machine's scheduling; it cannot go past what it had done at the kill
    double sim_before = 0;
    for (const auto& [wall, sim] : seen) {
        if (wall <= killed_at - 0.2 - 0.3) sim_before = sim;
    }
    INFO("last row " << last << " s, at kill " << sim_at_kill << " s, one flush before "
                     << sim_before << " s");
    CHECK(last >= sim_before);
    CHECK(last <= sim_at_kill + 0.3);
    // every row up to there reads back
    CHECK(static_cast<long>(t.size()) == run.rows());
    CHECK(run.get("snake.com.x").values.size() == t.size());
    const Run summary = cli({"data", tmp / "run"});
    CHECK(summary.status == 0);
    CHECK_THAT(summary.out,
               Catch::Contains("status   incomplete (the process ended without closing it)"));
    // and it replays up to where it stopped
    const Run replay = cli({"replay", tmp / "run"});
    CHECK(replay.status == 0);
    CHECK_THAT(replay.out, Catch::Contains("bit for bit (up to where the run stopped)"));
}

TEST_CASE("a full disk stops the run with one clear line and keeps what was written",
          "[cli][data]") {
    TempDir tmp("cli_full");
    // a file size limit stands in for a full disk: writes past 100 kB fail with EFBIG
    const std::string cmd = "trap '' XFSZ; ulimit -f 200; exec " + std::string(GAITLAB_BINARY) +
                            " run --record " + (tmp / "run") + " " + kScripts +
                            "/long_run.lua quiet";
    const pid_t pid = spawn({"sh", "-c", cmd}, tmp / "err");
    int wstatus = 0;
    REQUIRE(waitpid(pid, &wstatus, 0) == pid);
    REQUIRE(WIFEXITED(wstatus));
    CHECK(WEXITSTATUS(wstatus) == 1);
    CHECK(slurp(tmp / "err") ==
          "gaitlab: " + kScripts + "/long_run.lua:10: cannot write " + (tmp / "run/data.csv") +
              ": File too large (recording stopped; what was written before is kept)\n");
    const gaitlab::RunData run(tmp / "run");
    CHECK(run.rows() > 10);
    CHECK(run.meta().status == "failed");
    CHECK_THAT(run.log(), Catch::Contains("recording stopped at t = "));
    // the replay stops where the data does, as for a killed run
    const Run replay = cli({"replay", tmp / "run"});
    CHECK(replay.status == 0);
    CHECK_THAT(replay.out, Catch::Contains("bit for bit (up to where the run stopped)"));
    CHECK(gaitlab::RunData(tmp / "run-replay").rows() == run.rows());
}

namespace {

// waits until the file at `path` holds `text` (a spawned run's stderr), at most `seconds`
bool wait_for(const std::string& path, const std::string& text, double seconds = 30) {
    const double start = now_seconds();
    while (now_seconds() - start < seconds) {
        if (slurp(path).find(text) != std::string::npos) return true;
        usleep(10000);
    }
    return false;
}

// waits for a spawned process; its exit status, or -1 if it did not exit normally
int exit_status(pid_t pid) {
    int wstatus = 0;
    REQUIRE(waitpid(pid, &wstatus, 0) == pid);
    return WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
}

const char* signal_name(int sig) {
    return sig == SIGTERM ? "SIGTERM" : sig == SIGINT ? "SIGINT" : "SIGHUP";
}

}  // namespace

TEST_CASE("SIGTERM, SIGINT and SIGHUP close the run folder, which reads and replays",
          "[cli][data][signal]") {
    for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
        const std::string name = signal_name(sig);
        INFO(name);
        TempDir tmp(std::string("cli_signal_") + name);
        const std::string progress = tmp / "progress";
        const pid_t pid = spawn(
            {GAITLAB_BINARY, "run", "--record", tmp / "run", kScripts + "/long_run.lua"}, progress);
        // well into the run: past a flush or two
        double at = -1;
        const double start = now_seconds();
        while (now_seconds() - start < 30 && (at = last_progress(progress)) < 1.2)
            usleep(10000);
        REQUIRE(at >= 1.2);
        REQUIRE(kill(pid, sig) == 0);
        CHECK(exit_status(pid) == 128 + sig);
        // the last time the run reported before its message
        const std::string text = slurp(progress);
        const size_t message = text.find("gaitlab: ");
        REQUIRE(message != std::string::npos);
        write_text(tmp / "before", text.substr(0, message));
        const double sim_at_signal = last_progress(tmp / "before");
        CHECK_THAT(slurp(progress), Catch::EndsWith("gaitlab: interrupted (" + name + ")\n"));

        // closed: the data up to where it stopped, nothing cut short, run.json says how
        const gaitlab::RunData run(tmp / "run");
        CHECK(run.meta().status == "interrupted");
        CHECK(run.meta().message == name);
        CHECK(run.state() == "interrupted by " + name);
        CHECK_FALSE(run.truncated());
        const std::vector<double> t = run.times();
        REQUIRE(!t.empty());
        CHECK(t.back() >= sim_at_signal);  // every row the simulation made before it stopped
        CHECK(t.back() <= sim_at_signal + 0.3);
        CHECK(run.meta().last_tick >= std::lround(t.back() / 0.001));
        CHECK_THAT(run.log(), Catch::Contains("recording interrupted at t = "));

        const Run summary = cli({"data", tmp / "run"});
        CHECK(summary.status == 0);
        CHECK_THAT(summary.out, Catch::Contains("status   interrupted by " + name + "\n"));
        const Run replay = cli({"replay", tmp / "run"});
        CHECK(replay.status == 0);
        CHECK_THAT(replay.out,
                   Catch::StartsWith("replay identical: " + std::to_string(t.size()) + " rows x "));
        CHECK_THAT(replay.out, Catch::Contains("bit for bit (up to where the run stopped)"));
    }
}

TEST_CASE("a signal stops Lua code that swallows its errors, and keeps unflushed rows",
          "[cli][data][signal]") {
    TempDir tmp("cli_signal_busy");
    const std::string err = tmp / "err";
    // the flush period is a minute: everything after the first row is still in memory
    const pid_t pid =
        spawn({GAITLAB_BINARY, "run", "--record", tmp / "run", kScripts + "/busy.lua"}, err);
    REQUIRE(wait_for(err, "busy\n"));
    usleep(200000);
    REQUIRE(kill(pid, SIGTERM) == 0);
    CHECK(exit_status(pid) == 143);
    const gaitlab::RunData run(tmp / "run");
    CHECK(run.state() == "interrupted by SIGTERM");
    CHECK(run.rows() > 17);  // 0.5 s and more, though none of it had been flushed
    // its replay stops where it stopped, though the script catches every error
    const Run replay = cli({"replay", tmp / "run"});
    CHECK(replay.status == 0);
    CHECK_THAT(replay.out, Catch::Contains("bit for bit (up to where the run stopped)"));
}

TEST_CASE("a signal stops gaitlab replay and closes the replay's folder", "[cli][signal]") {
    TempDir tmp("cli_signal_replay");
    const std::string err = tmp / "err";
    pid_t pid = spawn(
        {GAITLAB_BINARY, "run", "--record", tmp / "run", kScripts + "/long_run.lua", "quiet"}, err);
    usleep(1500000);
    REQUIRE(kill(pid, SIGTERM) == 0);
    REQUIRE(exit_status(pid) == 143);
    // the replay takes about as long as the run: stopped well before its end
    pid = spawn({GAITLAB_BINARY, "replay", tmp / "run"}, err);
    const double start = now_seconds();
    while (now_seconds() - start < 30 && !std::filesystem::exists(tmp / "run-replay/data.csv"))
        usleep(1000);
    REQUIRE(kill(pid, SIGINT) == 0);
    CHECK(exit_status(pid) == 130);
    CHECK(slurp(err) == "gaitlab: interrupted (SIGINT)\n");
    const gaitlab::RunData replay(tmp / "run-replay");
    CHECK(replay.state() == "interrupted by SIGINT");
    CHECK(replay.rows() < gaitlab::RunData(tmp / "run").rows());
}

TEST_CASE("gaitlab data tells a run still being written from one whose process is gone",
          "[cli][data][signal]") {
    TempDir tmp("cli_alive");
    const std::string err = tmp / "err";
    const pid_t pid =
        spawn({GAITLAB_BINARY, "run", "--record", tmp / "run", kScripts + "/long_run.lua"}, err);
    REQUIRE(wait_for(err, "0.300\n"));
    const Run alive = cli({"data", tmp / "run"});
    CHECK(alive.status == 0);
    CHECK_THAT(alive.out, Catch::Contains("status   running (still being written by process " +
                                          std::to_string(pid) + ")\n"));
    // a second process recording into the same folder is refused; the first goes on
    const Run second = cli({"run", "--record", tmp / "run", kFirstSnake}, tmp.str());
    CHECK(second.status == 1);
    CHECK(second.err == "gaitlab: " + kFirstSnake + ":6: cannot record into " + (tmp / "run") +
                            ": another recording is writing into it (process " +
                            std::to_string(pid) + "); record into another folder\n");
    REQUIRE(kill(pid, SIGKILL) == 0);
    CHECK(exit_status(pid) == -1);
    const Run gone = cli({"data", tmp / "run"});
    CHECK_THAT(gone.out,
               Catch::Contains("status   incomplete (the process ended without closing it)\n"));
    CHECK(gaitlab::RunData(tmp / "run").series()[0].name == "snake.com.x");
}

TEST_CASE("output that cannot be written is an error, never a success", "[cli][data]") {
    TempDir tmp("cli_stdout");
    // (a machine where /dev/full was replaced by a regular file cannot run this test)
    struct stat dev_full {};
    REQUIRE(stat("/dev/full", &dev_full) == 0);
    REQUIRE(S_ISCHR(dev_full.st_mode));
    REQUIRE(cli({"run", "--record", tmp / "run", kFirstSnake}, tmp.str()).status == 0);
    const std::string dir = tmp / "run";
    for (const std::vector<std::string>& args :
         std::vector<std::vector<std::string>>{{"data", dir, "--series", "snake.com.x"},
                                               {"data", dir, "--series", "robot"},
                                               {"data", dir},
                                               {"data", dir, "--list"},
                                               {"data", dir, "--events"},
                                               {"--version"},
                                               {"--help"},
                                               {"run", "args.lua", "x"},
                                               {"run", "--record", tmp / "exits", "exits.lua"}}) {
        INFO(args[0] << " " << (args.size() > 1 ? args.back() : ""));
        const Run full = cli(args, kScripts, Out::full);
        CHECK(full.status == 1);
        CHECK_THAT(full.err, Catch::StartsWith("gaitlab: cannot write to standard output: "));
        CHECK(full.err.find('\n') == full.err.size() - 1);
        const Run closed = cli(args, kScripts, Out::closed);
        CHECK(closed.status == 1);
        CHECK_THAT(closed.err, Catch::StartsWith("gaitlab: cannot write to standard output: "));
        // a reader that went away: the quiet end SIGPIPE would give, not a success
        const Run pipe = cli(args, kScripts, Out::broken_pipe);
        CHECK(pipe.status == 128 + SIGPIPE);
        CHECK(pipe.err.empty());
    }
    // nothing that the run folder got went to the closed stdout instead
    const Run closed = cli({"run", "--record", tmp / "exits", "exits.lua"}, kScripts, Out::closed);
    CHECK(closed.status == 1);
    CHECK(gaitlab::RunData(tmp / "exits").meta().status == "finished");
    CHECK_THAT(gaitlab::RunData(tmp / "exits").log(), Catch::Contains("\nleaving\n"));
}

TEST_CASE("a broken pipe stops a printing run and closes its folder", "[cli][data][signal]") {
    TempDir tmp("cli_pipe");
    const Run r = cli({"run", "--record", tmp / "run", "printer.lua"}, kScripts, Out::broken_pipe);
    CHECK(r.status == 128 + SIGPIPE);
    CHECK(r.err.empty());
    const gaitlab::RunData run(tmp / "run");
    CHECK(run.state() == "interrupted by SIGPIPE");
    CHECK(run.rows() >= 2);
}

TEST_CASE("hostile names reach no shell or gnuplot command and no file outside --split DIR",
          "[cli][data]") {
    TempDir tmp("cli_hostile");
    // printable, so a valid robot name; names with line ends come only from run folders made
    // elsewhere (engine_plot_test covers them)
    const std::string name = "s`touch bq`$(touch dollar)\"; system(\"touch sys\"); \"' !touch nl";
    const Run r =
        cli({"run", "--record", tmp / "run", kScripts + "/hostile_names.lua", name}, tmp.str());
    REQUIRE(r.status == 0);
    const Run plot = cli({"data", tmp / "run", "--series", "robot", "--title", name, "--plot",
                          tmp / "out/p`touch fn`.png"},
                         tmp.str());
    CHECK(plot.status == 0);
    CHECK(std::filesystem::file_size(tmp / "out/p`touch fn`.png") > 5000);
    const Run path = cli({"data", tmp / "run", "--xy", name + ".com.x", name + ".com.y", "--title",
                          name, "--plot", tmp / "out/xy`touch fx`.png"},
                         tmp.str());
    CHECK(path.status == 0);
    CHECK(std::filesystem::file_size(tmp / "out/xy`touch fx`.png") > 5000);
    CHECK(slurp(tmp / "out/xy`touch fx`.csv").rfind("time,\"s`touch bq`", 0) == 0);
    const Run split =
        cli({"data", tmp / "run", "--series", "robot", "--split", tmp / "out/each"}, tmp.str());
    CHECK(split.status == 0);
    // what is there: the run, the plot's three files, the split folder; no file a command made
    std::vector<std::string> top;
    for (const auto& e : std::filesystem::directory_iterator(tmp.path))
        top.push_back(e.path().filename().string());
    std::sort(top.begin(), top.end());
    CHECK(top == std::vector<std::string>{"out", "run"});
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(tmp / "out"))
        out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    CHECK(out == std::vector<std::string>{"each", "p`touch fn`.csv", "p`touch fn`.gp",
                                          "p`touch fn`.png", "xy`touch fx`.csv", "xy`touch fx`.gp",
                                          "xy`touch fx`.png"});
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(tmp / "out/each")) {
        CHECK(e.is_regular_file());
        ++files;
    }
    CHECK(files == gaitlab::RunData(tmp / "run").names().size());
    // the summary and the list show no control characters from the run folder
    const Run list = cli({"data", tmp / "run", "--list"});
    CHECK(list.out.find(" !touch nl.com.x") != std::string::npos);
    // nor do messages quoting its content
    std::string data = slurp(tmp / "run/data.csv");
    const size_t row = data.find("\n0,") + 1;  // the first row, after the header's lines
    const std::string line =
        std::to_string(1 + std::count(data.begin(), data.begin() + static_cast<long>(row), '\n'));
    data.insert(row, "\x1b[2J");
    write_text(tmp / "run/data.csv", data);
    check_failure(cli({"data", tmp / "run", "--series", "robot"}),
                  "gaitlab: " + (tmp / "run/data.csv") + ":" + line +
                      ": column 'time': number expected, got '\\x1b[2J0'");
}

TEST_CASE("a FIFO, a device or a folder is no script: refused at once", "[cli]") {
    TempDir tmp("cli_not_file");
    REQUIRE(mkfifo((tmp / "fifo.lua").c_str(), 0600) == 0);
    std::filesystem::create_symlink("/dev/zero", tmp / "zero.lua");
    std::filesystem::create_directory(tmp / "dir.lua");
    check_failure(cli({"run", "fifo.lua"}, tmp.str()),
                  "gaitlab: fifo.lua: not a regular file (a FIFO, device or socket)");
    check_failure(cli({"zero.lua"}, tmp.str()),
                  "gaitlab: zero.lua: not a regular file (a FIFO, device or socket)");
    check_failure(cli({"run", "dir.lua"}, tmp.str()), "gaitlab: dir.lua: is a directory");
}

TEST_CASE("a script that leaves a simulation playing ends with a note", "[cli][progress]") {
    const Run r = cli({"run", "plays.lua"});
    CHECK(r.status == 0);
    CHECK(r.out == "true\n");
    CHECK(r.err ==
          "note: 1 simulation was left playing when the script ended: simulations play in the "
          "console (gaitlab -i plays.lua)\n");
}

TEST_CASE("a long run shows a progress line on a terminal only", "[cli][progress]") {
    // piped or redirected: not a byte more than without it
    const Run piped = cli({"run", "progress.lua"});
    CHECK(piped.status == 0);
    CHECK(piped.out == "done at t = 6.0\n");
    CHECK(piped.err.empty());

    // on a terminal (script(1) gives the command a pseudo-terminal and copies what it shows)
    TempDir dir("cli_progress");
    const std::string shown = dir.file("shown");
    const std::string command = std::string("script -qfec '") + GAITLAB_BINARY +
                                " run --no-record progress.lua' " + shown + " > /dev/null";
    const std::string cd = "cd '" + kScripts + "' && ";
    REQUIRE(std::system((cd + command).c_str()) == 0);
    const std::string screen = slurp(shown);
    INFO(screen);
    CHECK_THAT(screen, Catch::Matches(R"([\s\S]*\rt = [0-9.]+ / 6 s \([0-9]+%\), [0-9.e+]+x real )"
                                      R"(time, (<1|[0-9]+) s left\x1b\[K[\s\S]*)"));
    // taken away before the data
    CHECK_THAT(screen, Catch::Contains("\r\x1b[Kdone at t = 6.0\r\n"));

    // --no-progress: none on the terminal either
    const std::string quiet = dir.file("quiet");
    const std::string off = std::string("script -qfec '") + GAITLAB_BINARY +
                            " run --no-record --no-progress progress.lua' " + quiet +
                            " > /dev/null";
    REQUIRE(std::system((cd + off).c_str()) == 0);
    const std::string plain = slurp(quiet);
    INFO(plain);
    CHECK(plain.find("real time") == std::string::npos);
    CHECK(plain.find("\x1b") == std::string::npos);
    CHECK_THAT(plain, Catch::Contains("done at t = 6.0\r\n"));
}

TEST_CASE(
    "gaitlab check runs a simulation file again at finer settings and says whether it "
    "moved",
    "[cli][check]") {
    // the walk at its own settings: within 3 %, status 0, one line per robot
    const Run r =
        cli({"check", "examples/walk.xml", "--seconds", "4", "--cycle", "2"}, GAITLAB_SOURCE_DIR);
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK_THAT(r.out,
               Catch::Matches(".*/examples/walk\\.xml: the paths from 0 to 4 s, sampled every "
                              "2 s, at the file's dt 1 ms and 20 iterations, at dt 0\\.25 ms and "
                              "with 80 iterations\nsnake: path [0-9]+\\.[0-9] mm; at dt / 4 "
                              "[0-9]+\\.[0-9] mm \\([+-][0-2]\\.[0-9] %\\); with 4x the "
                              "iterations [0-9]+\\.[0-9] mm \\([+-][0-2]\\.[0-9] %\\)\nwithin 3 "
                              "% at both finer settings\n"));

    // the same walk with pgs and 2 iterations: both settings warned, status 3
    TempDir tmp("cli_check");
    namespace fs = std::filesystem;
    fs::copy(GAITLAB_SOURCE_DIR "/examples/walk", tmp / "walk", fs::copy_options::recursive);
    fs::copy(GAITLAB_SOURCE_DIR "/examples/controllers", tmp / "controllers",
             fs::copy_options::recursive);
    std::string sim = slurp(GAITLAB_SOURCE_DIR "/examples/walk.xml");
    sim.replace(sim.find("seed=\"0\""), 8, "seed=\"0\" solver=\"pgs\" solver_iterations=\"2\"");
    std::ofstream(tmp / "coarse.xml") << sim;
    const Run c = cli({"check", "coarse.xml", "--seconds", "6", "--cycle", "2"}, tmp.str());
    CHECK(c.status == 3);
    // nothing recorded where it ran
    CHECK(fs::exists(tmp / "coarse.xml"));
    CHECK_FALSE(fs::exists(tmp / "runs"));
    CHECK_THAT(c.err, Catch::Contains("gaitlab: warning: solver_iterations = 2 is below 15"));
    CHECK_THAT(c.err, Catch::Contains("gaitlab: warning: dt = 1 ms: robot 'snake' moves "));
    CHECK_THAT(c.err, Catch::Contains("gaitlab: warning: solver_iterations = 2: robot 'snake' "
                                      "moves "));
    CHECK_THAT(c.out, Catch::EndsWith("2 setting(s) move a robot by more than 3 % (the warnings "
                                      "above)\n"));

    // bad input: named, one line, before anything runs
    const std::string help = " (see 'gaitlab check --help')";
    check_failure(cli({"check", "examples/walk.xml", "--seconds", "0"}, GAITLAB_SOURCE_DIR),
                  "gaitlab: --seconds: a number of seconds > 0 expected (got '0')" + help);
    check_failure(cli({"check", "examples/walk.xml", "--cycle", "x"}, GAITLAB_SOURCE_DIR),
                  "gaitlab: --cycle: a number of seconds expected (got 'x')" + help);
    check_failure(
        cli({"check", "examples/walk.xml", "--settle", "-1"}, GAITLAB_SOURCE_DIR),
        "gaitlab: --settle: a number of seconds from 0 to 1e6 expected (got '-1')" + help);
    // a length no simulation can run was blamed on the file's line 5 and a Lua field
    check_failure(
        cli({"check", "examples/walk.xml", "--seconds", "1e300"}, GAITLAB_SOURCE_DIR),
        "gaitlab: --seconds: a number of seconds up to 1e6 expected (got '1e300')" + help);
    check_failure(cli({"check", "examples/walk.xml", "--seconds", "inf"}, GAITLAB_SOURCE_DIR),
                  "gaitlab: --seconds: a number of seconds expected (got 'inf')" + help);
    const std::string walk = std::string(GAITLAB_SOURCE_DIR) + "/examples/walk.xml";
    check_failure(
        cli({"check", walk, "--settle", "30"}),
        "gaitlab: " + walk + ":5: the settling time (30 s) must be shorter than the check (20 s)");
    check_failure(cli({"check", walk, "--settle", "2", "--seconds", "4", "--cycle", "3"}),
                  "gaitlab: " + walk +
                      ":5: the cycle (3 s) must be from dt (0.001 s) to the time checked after "
                      "the settling time (2 s)");
    check_failure(cli({"check", "examples/first_snake.lua"}, GAITLAB_SOURCE_DIR),
                  "gaitlab: examples/first_snake.lua: expected a simulation file (FILE.xml); a "
                  "Lua script checks its simulation itself with sim:check_accuracy{} "
                  "(docs/lua-api.md)");
    check_failure(
        cli({"check", tmp / "none.xml"}),
        "gaitlab: " + (tmp / "none.xml") + ": cannot read the file: No such file or directory");
    fs::create_directory(tmp / "folder.xml");
    check_failure(cli({"check", tmp / "folder.xml"}),
                  "gaitlab: " + (tmp / "folder.xml") + ": is a directory");
}

TEST_CASE("a signal stops gaitlab check midway, with one line", "[cli][check][signal]") {
    for (int sig : {SIGINT, SIGTERM}) {
        const std::string name = signal_name(sig);
        INFO(name);
        TempDir tmp(std::string("cli_check_signal_") + name);
        const std::string err = tmp / "err";
        // 300 s of the walk at three settings: minutes of work, stopped after 1.5 s (past the
        // start-up, where the signal handlers are set, also under the sanitizers)
        const pid_t pid = spawn(
            {GAITLAB_BINARY, "check", GAITLAB_SOURCE_DIR "/examples/walk.xml", "--seconds", "300"},
            err);
        usleep(1500000);
        const double start = now_seconds();
        REQUIRE(kill(pid, sig) == 0);
        CHECK(exit_status(pid) == 128 + sig);
        CHECK(now_seconds() - start < 10);
        CHECK(slurp(err) == "gaitlab: interrupted (" + name + ")\n");
    }
}

TEST_CASE("gaitlab data's summary gives times with the time step's decimals", "[cli][data]") {
    TempDir tmp("cli_data_times");
    // the last row's time, tick 570 × 0.001 s, is 0.5700000000000001 in data.csv
    write_text(tmp / "short.lua",
               "local robot = gaitlab.robot.chain{ name = 'snake', modules = 2 }\n"
               "local world = gaitlab.world{}\n"
               "world:add(robot)\n"
               "gaitlab.simulation{ world = world }:run(0.57)\n");
    REQUIRE(cli({"run", "--record", tmp / "run", tmp / "short.lua"}, tmp.str()).status == 0);
    const Run summary = cli({"data", tmp / "run"});
    CHECK(summary.status == 0);
    CHECK_THAT(summary.out,
               Catch::Contains("rows     20, t = 0 .. 0.57 s, every 30 ticks of 0.001 s\n"));
    // the CSV keeps every digit
    const Run csv = cli({"data", tmp / "run", "--series", "snake.com.x"});
    CHECK_THAT(csv.out, Catch::Contains("\n0.5700000000000001,"));
}
