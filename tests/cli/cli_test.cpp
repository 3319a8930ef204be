// The gaitlab executable (cli/main.cpp), run as users run it: exit status, stdout and the exact
// text on stderr. Failing runs print exactly one line, "gaitlab: FILE:LINE: message".
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace {

const std::string kScripts = GAITLAB_SOURCE_DIR "/tests/cli/scripts";

// a fresh folder for one test, removed with what it holds (temp_dir.h's, which cannot be used
// here: its namespace gaitlab would hide the gaitlab() helper below)
struct TempDir {
    explicit TempDir(const std::string& name) {
        std::string t = "/tmp/gaitlab_" + name + ".XXXXXX";
        path = mkdtemp(t.data()) ? t : std::string();
        REQUIRE(!path.empty());
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    std::string operator/(const std::string& name) const { return path + "/" + name; }
    std::string str() const { return path; }
    std::string path;
};

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

// runs the gaitlab executable with `args` in directory `cwd`, capturing stdout and stderr.
// `gaitlab run` records by default: the tests record only where they say (--record DIR), so
// the source tree stays clean
Run gaitlab(std::vector<std::string> args, const std::string& cwd = kScripts) {
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
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0600);
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
    const Run r = gaitlab({GAITLAB_SOURCE_DIR "/examples/first_snake.lua"}, cwd.str());
    CHECK(r.status == 0);
    CHECK_THAT(r.out, Catch::Matches(R"(moved [0-9.]+ m \(x -?[0-9.]+, y -?[0-9.]+\)\n)"));
    CHECK_THAT(r.err, Catch::Matches(R"(recorded runs/first_snake-[0-9]{8}-[0-9]{6}\n)"));
    const std::string dir = cwd / r.err.substr(9, r.err.size() - 10);
    CHECK(std::filesystem::exists(dir + "/data.csv"));
    // same simulation, same output
    const Run s = gaitlab({"run", "examples/first_snake.lua"}, GAITLAB_SOURCE_DIR);
    CHECK(s.status == 0);
    CHECK(s.err.empty());
    CHECK(s.out == r.out);
}

TEST_CASE("version and help options", "[cli]") {
    const Run v = gaitlab({"--version"});
    CHECK(v.status == 0);
    CHECK_THAT(v.out, Catch::Matches(R"(gaitlab [0-9]+\.[0-9]+\.[0-9]+\n)"));
    CHECK(v.err.empty());

    const Run h = gaitlab({"--help"});
    CHECK(h.status == 0);
    CHECK_THAT(h.out, Catch::Contains("Usage: gaitlab"));
    CHECK_THAT(h.out, Catch::Contains("run"));
    CHECK(h.err.empty());

    const Run rh = gaitlab({"run", "--help"});
    CHECK(rh.status == 0);
    CHECK_THAT(rh.out, Catch::Contains("--seed"));
}

TEST_CASE("a missing script fails with one line naming it", "[cli]") {
    const Run r = gaitlab({"run", "no_such_script.lua"});
    CHECK(r.status > 0);
    CHECK_THAT(r.err, Catch::StartsWith("gaitlab: cannot open no_such_script.lua"));
    CHECK(r.err.find('\n') == r.err.size() - 1);
    check_failure(r, r.err.substr(0, r.err.size() - 1));

    const Run b = gaitlab({"no_such_script.lua"});
    CHECK(b.status == r.status);
    CHECK(b.err == r.err);

    check_failure(gaitlab({"run", "notes.txt"}),
                  "gaitlab: notes.txt: expected a Lua script (FILE.lua)");
}

TEST_CASE("script errors print one line: gaitlab: FILE:LINE: message", "[cli]") {
    check_failure(gaitlab({"run", "syntax_error.lua"}),
                  "gaitlab: syntax_error.lua:3: '}' expected near 'end'");
    check_failure(gaitlab({"run", "runtime_error.lua"}),
                  "gaitlab: runtime_error.lua:4: attempt to call a nil value (field 'populate')");
    check_failure(gaitlab({"run", "unknown_key.lua"}),
                  "gaitlab: unknown_key.lua:2: bad argument #1 to 'chain' (unknown key "
                  "'conection'; did you mean 'connection'?)");
    check_failure(gaitlab({"run", "out_of_range.lua"}),
                  "gaitlab: out_of_range.lua:7: sine.amplitude must be in [0, 90] deg (got 120)");
    // the file is named as the user gave it
    check_failure(gaitlab({"run", kScripts + "/runtime_error.lua"}, "/"),
                  "gaitlab: " + kScripts +
                      "/runtime_error.lua:4: attempt to call a nil value (field 'populate')");
    check_failure(gaitlab({"scripts/unknown_key.lua"}, GAITLAB_SOURCE_DIR "/tests/cli"),
                  "gaitlab: scripts/unknown_key.lua:2: bad argument #1 to 'chain' (unknown key "
                  "'conection'; did you mean 'connection'?)");
}

TEST_CASE("a controller error names the controller file and line", "[cli]") {
    const std::string message =
        "controllers/bad_step.lua:5: attempt to perform arithmetic on a nil value (field 'gain')";
    check_failure(gaitlab({"run", "controller_error.lua"}), "gaitlab: " + message);
    // controller paths resolve against the folder of the script that loads them
    check_failure(gaitlab({"run", "scripts/controller_error.lua"}, GAITLAB_SOURCE_DIR "/tests/cli"),
                  "gaitlab: scripts/" + message);
}

TEST_CASE("scripts get their arguments in arg", "[cli]") {
    const Run r = gaitlab({"args.lua", "one", "two words", "--three", "-4"});
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK(r.out == "args.lua\n1\tone\n2\ttwo words\n3\t--three\n4\t-4\n");

    const Run none = gaitlab({"run", "args.lua"});
    CHECK(none.out == "args.lua\n");

    // gaitlab's own options may come before or right after FILE; the rest is the script's
    const Run seeded = gaitlab({"run", "args.lua", "--seed", "3", "x"});
    CHECK(seeded.status == 0);
    CHECK(seeded.out == "args.lua\n1\tx\n");
    const Run after = gaitlab({"run", "args.lua", "x", "--seed", "3"});
    CHECK(after.out == "args.lua\n1\tx\n2\t--seed\n3\t3\n");
}

TEST_CASE("the seed option makes math.random reproducible", "[cli]") {
    const Run a = gaitlab({"run", "--seed", "11", "random.lua"});
    const Run b = gaitlab({"run", "--seed", "11", "random.lua"});
    const Run c = gaitlab({"run", "--seed", "12", "random.lua"});
    const Run d = gaitlab({"run", "random.lua", "--seed", "12"});
    const Run e = gaitlab({"random.lua"});
    const Run f = gaitlab({"run", "--seed", "0", "random.lua"});
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
    check_failure(gaitlab({"run", "--seed", "many", "random.lua"}),
                  "gaitlab: Could not convert: --seed = many (see 'gaitlab --help')");
    check_failure(gaitlab({"run"}), "gaitlab: file is required (see 'gaitlab --help')");
    check_failure(gaitlab({"launch"}),
                  "gaitlab: The following argument was not expected: launch (see 'gaitlab "
                  "--help')");
}
