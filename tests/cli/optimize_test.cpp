// `gaitlab optimize` (cli/optimize.cpp), run as users run it: a small spec end to end (the
// progress lines, the results folder, the same evaluations with 1 and 2 workers), and bad
// options and spec files (one line on stderr, no results folder), SIGINT.
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>

#include <filesystem>
#include <string>
#include <vector>

#include "run_gaitlab.h"

using namespace gaitlab::test;

namespace {

// quick evaluations: half a second each
const std::string kSpec =
    snake_spec(R"(duration = 0.5, method = "ga", population = 5, generations = 3)");

}  // namespace

TEST_CASE("gaitlab optimize: a spec runs end to end and writes its results folder") {
    TempDir dir("cli_optimize");
    write_text(dir / "spec.lua", kSpec);
    const auto r = run_gaitlab(
        {"optimize", "spec.lua", "--workers", "2", "--seed", "5", "--out", "out2"}, dir.str());
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());
    const std::vector<std::string> out = lines(r.out);
    REQUIRE(out.size() == 9);
    CHECK(out[0] ==
          "optimize spec.lua: 2 parameters (amplitude, phase), fitness distance, 2 workers, "
          "results in out2");
    CHECK(out[1].rfind("generation 1/3: best ", 0) == 0);
    CHECK(out[3].rfind("generation 3/3: best ", 0) == 0);
    CHECK(out[4].rfind("best distance ", 0) == 0);
    CHECK(out[4].find(" after 11 evaluations (ga, seed 5): amplitude = ") != std::string::npos);
    CHECK(out[5] == "results: out2/evaluations.jsonl, out2/best.json");
    CHECK(out[6] == "the best as a simulation file: gaitlab run out2/best/best.xml");
    CHECK(out[7] == "the best's run recorded: gaitlab view out2/run, gaitlab data out2/run --list");
    CHECK(out[8] == "convergence plot: out2/convergence.png");
    // the best's run, recorded: a run folder gaitlab data reads
    const auto data = run_gaitlab({"data", "out2/run"}, dir.str());
    CHECK(data.status == 0);
    CHECK(data.out.find("status   finished\n") != std::string::npos);
    CHECK(data.out.find("rows     17, t = 0 .. 0.48 s") != std::string::npos);
    const auto com = run_gaitlab({"data", "out2/run", "--series", "snake.com.x"}, dir.str());
    CHECK(com.status == 0);
    CHECK(lines(com.out).size() == 18);
    // the convergence plot: a PNG, and its data, one row per generation, the best so far
    // never falling and ending at the run's best
    const std::string png = read_text(dir / "out2/convergence.png");
    CHECK(png.substr(0, 8) == "\x89PNG\r\n\x1a\n");
    CHECK(png.size() > 5000);
    const std::vector<std::string> rows = lines(read_text(dir / "out2/convergence.csv"));
    REQUIRE(rows.size() == 4);
    CHECK(rows[0] == "generation,best so far,generation mean");
    double previous = 0;
    std::string last_best;
    for (size_t i = 1; i < rows.size(); ++i) {
        CHECK(rows[i].rfind(std::to_string(i) + ",", 0) == 0);
        const size_t a = rows[i].find(','), b = rows[i].find(',', a + 1);
        last_best = rows[i].substr(a + 1, b - a - 1);
        CHECK(std::stod(last_best) >= previous);
        previous = std::stod(last_best);
    }
    // which runs
    const auto run = run_gaitlab({"run", "--no-record", "out2/best/best.xml"}, dir.str());
    CHECK(run.status == 0);
    CHECK(run.out.rfind("snake: moved ", 0) == 0);
    // 5 + 3 + 3 evaluations (2 elites carried over)
    const std::vector<std::string> two = timeless(dir / "out2/evaluations.jsonl");
    CHECK(two.size() == 11);
    const std::string best = read_text(dir / "out2/best.json");
    CHECK(best.find("\"method\": \"ga\"") != std::string::npos);
    CHECK(best.find("\"seed\": 5") != std::string::npos);
    CHECK(best.find("\"amplitude\": ") != std::string::npos);
    CHECK(best.find("\"fitness\": " + last_best + ",\n") != std::string::npos);
    CHECK(best.find("\"plot\": \"convergence.png\"") != std::string::npos);
    CHECK(best.find("\"run\": \"run\"") != std::string::npos);

    // one worker: the same evaluations, in the same order
    const auto r1 =
        run_gaitlab({"optimize", "spec.lua", "--seed", "5", "--out", "out1"}, dir.str());
    REQUIRE(r1.status == 0);
    CHECK(timeless(dir / "out1/evaluations.jsonl") == two);
    CHECK(lines(r1.out)[4] == out[4]);

    // the command line overrides the spec's method, population and generations
    const auto r2 = run_gaitlab({"optimize", "spec.lua", "--method", "pgpe", "--population", "4",
                                 "--generations", "2", "--out", "pgpe"},
                                dir.str());
    REQUIRE(r2.status == 0);
    CHECK(timeless(dir / "pgpe/evaluations.jsonl").size() == 8);
    CHECK(r2.out.find("after 8 evaluations (pgpe, seed 0)") != std::string::npos);
}

TEST_CASE("gaitlab optimize: one parameter is one parameter") {
    TempDir dir("cli_optimize_one");
    std::string spec =
        snake_spec(R"(duration = 0.2, method = "ga", population = 4, generations = 1)");
    const auto cut = [&](const std::string& from, const std::string& to) {
        const size_t at = spec.find(from);
        REQUIRE(at != std::string::npos);
        spec.replace(at, from.size(), to);
    };
    cut(", phase = {30, 180, initial = 120}", "");
    cut("phase = p.phase", "phase = 120");
    write_text(dir / "spec.lua", spec);
    const auto r =
        run_gaitlab({"optimize", "spec.lua", "--workers", "1", "--out", "out"}, dir.str());
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(lines(r.out).at(0) ==
          "optimize spec.lua: 1 parameter (amplitude), fitness distance, 1 worker, results in out");
}

TEST_CASE("gaitlab optimize: bad options and spec files give one line and no results") {
    TempDir dir("cli_optimize_bad");
    write_text(dir / "spec.lua", kSpec);
    struct Case {
        std::vector<std::string> args;
        int status;
        std::string err;
    };
    const std::vector<Case> cases = {
        {{"optimize", "spec.lua", "--workers", "0"},
         2,
         "gaitlab: --workers: a whole number from 1 to 1024 expected (got '0') (see 'gaitlab "
         "optimize --help')\n"},
        {{"optimize", "spec.lua", "--generations", "x"},
         2,
         "gaitlab: --generations: a whole number from 1 to 1000000000 expected (got 'x') (see "
         "'gaitlab optimize --help')\n"},
        {{"optimize", "spec.lua", "--method", "sga"},
         2,
         "gaitlab: --method: unknown method 'sga' (expected ga, cmaes or pgpe) (see 'gaitlab "
         "optimize --help')\n"},
        {{"optimize", "spec.lua", "--generation", "3"},
         2,
         "gaitlab: unknown option '--generation' for 'gaitlab optimize'; did you mean "
         "'--generations'? (see 'gaitlab optimize --help')\n"},
        {{"optimize", "none.lua"},
         1,
         "gaitlab: none.lua: no such file (an optimization spec, FILE.lua, expected)\n"},
    };
    for (const Case& c : cases) {
        const auto r = run_gaitlab(c.args, dir.str());
        INFO(c.err);
        CHECK(r.status == c.status);
        CHECK(r.err == c.err);
        CHECK(r.out.empty());
    }
    write_text(dir / "nobuild.lua",
               "return { parameters = { a = {0, 1} }, fitness = 'speed', duration = 1 }");
    const auto r = run_gaitlab({"optimize", "nobuild.lua", "--out", "out"}, dir.str());
    CHECK(r.status == 1);
    CHECK(r.err ==
          "gaitlab: nobuild.lua: build: missing (a function(p) that returns a simulation "
          "expected)\n");
    CHECK_FALSE(std::filesystem::exists(dir / "out"));
    // an evaluation that fails for every individual: the run ends and says so
    write_text(dir / "fails.lua",
               "return { parameters = { a = {0, 1} }, fitness = 'speed', duration = 1,\n"
               "  build = function(p) error('cannot build') end, method = 'ga', population = 4,\n"
               "  generations = 1 }\n");
    const auto f = run_gaitlab({"optimize", "fails.lua", "--out", "fails"}, dir.str());
    CHECK(f.status == 1);
    CHECK(f.err == "gaitlab: every evaluation failed (see fails/evaluations.jsonl)\n");
    CHECK(f.out.find("(4 failed: fails.lua:2: cannot build)") != std::string::npos);
    CHECK(lines(read_text(dir / "fails/evaluations.jsonl")).size() == 4);
}

TEST_CASE("gaitlab optimize: SIGINT stops the evaluations under way and writes nothing half done") {
    TempDir dir("cli_optimize_signal");
    // long evaluations: a generation takes seconds, so the signal comes during one
    write_text(dir / "long.lua",
               snake_spec(R"(duration = 30, method = "ga", population = 5, generations = 50)"));
    const std::string out = dir / "out";
    const std::string err_path = dir / "err";
    const auto stopped = interrupt_while_evaluating(
        {"optimize", dir / "long.lua", "--out", out, "--population", "4"}, "", out, dir / "stdout",
        err_path);
    // the evaluations under way stop at once, not after their 30 simulated seconds
    CHECK(stopped.seconds < 3);
    REQUIRE(WIFEXITED(stopped.wstatus));
    CHECK(WEXITSTATUS(stopped.wstatus) == 128 + SIGINT);
    CHECK(read_text(err_path) == "gaitlab: interrupted; the evaluations so far are in " + out +
                                     " (go on with --resume --out " + out + ")\n");
    // nothing half-written: the generation under way is not in the file
    CHECK(read_text(out + "/evaluations.jsonl").empty());
    CHECK_FALSE(std::filesystem::exists(out + "/best.json"));
}

TEST_CASE("gaitlab optimize: a full disk names the reason and leaves no temporary file") {
    TempDir dir("cli_optimize_full");
    write_text(dir / "spec.lua", kSpec);
    REQUIRE(run_gaitlab({"optimize", "spec.lua", "--out", "out"}, dir.str()).status == 0);
    // best.json written again by --resume into a file every write of which fails (ENOSPC)
    std::filesystem::remove(dir / "out/best.json");
    std::filesystem::create_symlink("/dev/full", dir / "out/best.json.tmp");
    const auto r = run_gaitlab({"optimize", "spec.lua", "--resume", "--out", "out"}, dir.str());
    CHECK(r.status == 1);
    CHECK(r.err == "gaitlab: out/best.json.tmp: cannot write: No space left on device\n");
    CHECK_FALSE(std::filesystem::is_symlink(dir / "out/best.json.tmp"));
    CHECK_FALSE(std::filesystem::exists(dir / "out/best.json"));
}

TEST_CASE("gaitlab optimize: a best's run that cannot be recorded is named in best.json") {
    TempDir dir("cli_optimize_fsize");
    write_text(dir / "spec.lua", kSpec);
    // a file size limit (20 kB) stands in for a disk that fills up while the run is recorded
    const std::string cmd = "cd " + dir.str() + " && (trap '' XFSZ; ulimit -f 20; exec " +
                            GAITLAB_BINARY + " optimize spec.lua --out out) >out.txt 2>err.txt";
    REQUIRE(std::system(cmd.c_str()) == 0);
    CHECK(read_text(dir / "out.txt")
              .find("the best's run could not be recorded: cannot write out/run/data.csv: File "
                    "too large") != std::string::npos);
    const std::string best = read_text(dir / "out/best.json");
    CHECK(best.find("\"run_error\": \"cannot write out/run/data.csv: File too large") !=
          std::string::npos);
    CHECK(best.find("\"run\": ") == std::string::npos);
}
