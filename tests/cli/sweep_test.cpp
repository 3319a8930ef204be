// `gaitlab sweep` (cli/sweep.cpp), run as users run it: a small grid end to end (the lines it
// prints, the results folder, the same table with 1 and 2 workers, the best as a simulation
// file that runs), a failing point, bad options and grids (one line on stderr, status 2, no
// results folder), SIGINT.
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>

#include <filesystem>
#include <string>
#include <vector>

#include "run_gaitlab.h"

using namespace gaitlab::test;

namespace {

// quick evaluations, half a second each, but for one point that fails (at line 4)
const std::string kFailsAt20And60 =
    R"(if p.amplitude == 20 and p.phase == 60 then error("amplitude 20 at phase 60") end)";
const std::string kSpec = snake_spec("duration = 0.5", kFailsAt20And60);

}  // namespace

TEST_CASE("gaitlab sweep: a grid runs end to end and writes its results folder") {
    TempDir dir("cli_sweep");
    write_text(dir / "spec.lua", kSpec);
    const auto r = run_gaitlab({"sweep", "spec.lua", "--grid", "amplitude=20:60:20",
                                "phase=60:180:60", "--workers", "2", "--out", "two"},
                               dir.str());
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());  // no progress line when stderr is not a terminal
    const std::vector<std::string> out = lines(r.out);
    REQUIRE(out.size() == 6);
    CHECK(out[0] ==
          "sweep spec.lua: amplitude, phase on a 3 x 3 grid (9 points), fitness distance, 2 "
          "workers, results in two");
    CHECK(out[1] == "1 of 9 points failed (the first: spec.lua:4: amplitude 20 at phase 60)");
    CHECK(out[2].rfind("best distance ", 0) == 0);
    CHECK(out[3] == "results: two/sweep.csv, two/evaluations.jsonl, two/best.json");
    CHECK(out[4] == "plot: two/sweep.png");
    CHECK(out[5] == "the best as a simulation file: gaitlab run two/best/best.xml");
    // the table: every point in grid order, the failed one marked
    const std::vector<std::string> table = lines(read_text(dir / "two/sweep.csv"));
    REQUIRE(table.size() == 10);
    CHECK(table[0] == "amplitude,phase,fitness,error");
    CHECK(table[1] == "20,60,NaN,spec.lua:4: amplitude 20 at phase 60");
    const char* points[] = {"20,60,",  "20,120,", "20,180,", "40,60,", "40,120,",
                            "40,180,", "60,60,",  "60,120,", "60,180,"};
    double best = -1;
    std::string best_row;
    for (int i = 0; i < 9; ++i) {
        const std::string& row = table[static_cast<std::size_t>(i + 1)];
        CHECK(row.rfind(points[i], 0) == 0);
        if (i == 0) continue;
        const double f = std::stod(row.substr(std::string(points[i]).size()));
        if (f > best) {
            best = f;
            best_row = row;
        }
    }
    // the best line names the table's best row
    const std::string a = best_row.substr(0, best_row.find(','));
    const std::string rest = best_row.substr(a.size() + 1);
    const std::string ph = rest.substr(0, rest.find(','));
    CHECK(out[2].find("amplitude = " + a + ", phase = " + ph) != std::string::npos);
    CHECK(timeless(dir / "two/evaluations.jsonl").size() == 9);
    // the plot is a PNG
    const std::string png = read_text(dir / "two/sweep.png");
    CHECK(png.substr(0, 8) == "\x89PNG\r\n\x1a\n");
    // the best runs
    const auto run = run_gaitlab({"run", "--no-record", "two/best/best.xml"}, dir.str());
    CHECK(run.status == 0);
    CHECK(run.out.rfind("snake: moved ", 0) == 0);

    // one worker: the same table and evaluations
    const auto r1 = run_gaitlab(
        {"sweep", "spec.lua", "--grid", "amplitude=20:60:20", "phase=60:180:60", "--out", "one"},
        dir.str());
    REQUIRE(r1.status == 0);
    CHECK(read_text(dir / "one/sweep.csv") == read_text(dir / "two/sweep.csv"));
    CHECK(timeless(dir / "one/evaluations.jsonl") == timeless(dir / "two/evaluations.jsonl"));
    CHECK(lines(r1.out)[2] == out[2]);
}

TEST_CASE("gaitlab sweep: bad options and grids give one line and no results") {
    TempDir dir("cli_sweep_bad");
    write_text(dir / "spec.lua", kSpec);
    struct Case {
        std::vector<std::string> args;
        int status;
        std::string err;
    };
    const std::string see = " (see 'gaitlab sweep --help')\n";
    const std::vector<Case> cases = {
        {{"sweep", "spec.lua"}, 2, "gaitlab: --grid is required (see 'gaitlab sweep --help')\n"},
        {{"sweep", "spec.lua", "--grid", "phase=30:180", "--out", "out"},
         2,
         "gaitlab: --grid 'phase=30:180': NAME=FROM:TO:STEP expected, e.g. phase=30:180:15" + see},
        {{"sweep", "spec.lua", "--grid", "phases=30:180:15", "--out", "out"},
         2,
         "gaitlab: --grid 'phases=30:180:15': unknown parameter 'phases'; did you mean "
         "'phase'? (the spec's parameters: amplitude, phase)" +
             see},
        {{"sweep", "spec.lua", "--grid", "phase=30:180:0", "--out", "out"},
         2,
         "gaitlab: --grid 'phase=30:180:0': STEP 0: a step > 0 expected" + see},
        {{"sweep", "spec.lua", "--grid", "phase=180:30:15", "--out", "out"},
         2,
         "gaitlab: --grid 'phase=180:30:15': the range 180:30 is inverted (FROM < TO expected)" +
             see},
        {{"sweep", "spec.lua", "--grid", "phase=0:180:15", "--out", "out"},
         2,
         "gaitlab: --grid 'phase=0:180:15': 0 is outside phase's range [30, 180] in spec.lua" +
             see},
        {{"sweep", "spec.lua", "--grid", "phase=30:180:1", "amplitude=10:60:0.01", "--out", "out"},
         2,
         "gaitlab: --grid: 151 x 5001 = 755151 points; a grid has at most 100000" + see},
        {{"sweep", "spec.lua", "--grid", "phase=30:180:15", "--workers", "0"},
         2,
         "gaitlab: --workers: a whole number from 1 to 1024 expected (got '0')" + see},
        {{"sweep", "none.lua", "--grid", "phase=30:180:15"},
         1,
         "gaitlab: none.lua: no such file (an optimization spec, FILE.lua, expected)\n"},
    };
    for (const Case& c : cases) {
        const auto r = run_gaitlab(c.args, dir.str());
        INFO(c.err);
        CHECK(r.status == c.status);
        CHECK(r.err == c.err);
        CHECK(r.out.empty());
        CHECK_FALSE(std::filesystem::exists(dir / "out"));
    }
    // a results folder that holds something is kept as it is
    std::filesystem::create_directories(dir / "full");
    write_text(dir / "full/keep.txt", "earlier results");
    const auto full =
        run_gaitlab({"sweep", "spec.lua", "--grid", "phase=30:180:75", "--out", "full"}, dir.str());
    CHECK(full.status == 1);
    CHECK(full.err ==
          "gaitlab: --out full: the folder exists and is not empty (an earlier run's results "
          "are kept: choose another folder)\n");
    CHECK(read_text(dir / "full/keep.txt") == "earlier results");
    // every point failing: the table, and status 1
    write_text(dir / "fails.lua",
               "return { parameters = { a = {0, 1} }, fitness = 'speed', duration = 1,\n"
               "  build = function(p) error('cannot build') end }\n");
    const auto f =
        run_gaitlab({"sweep", "fails.lua", "--grid", "a=0:1:0.5", "--out", "fails"}, dir.str());
    CHECK(f.status == 1);
    CHECK(f.err == "gaitlab: every point failed (see fails/sweep.csv)\n");
    CHECK(f.out.find("3 of 3 points failed (the first: fails.lua:2: cannot build)") !=
          std::string::npos);
    CHECK(lines(read_text(dir / "fails/sweep.csv")).size() == 4);
}

TEST_CASE("gaitlab sweep: SIGINT stops the evaluations under way") {
    TempDir dir("cli_sweep_signal");
    write_text(dir / "long.lua", snake_spec("duration = 30", kFailsAt20And60));
    const std::string out = dir / "out";
    const std::string err_path = dir / "err";
    const auto stopped = interrupt_while_evaluating(
        {"sweep", dir / "long.lua", "--grid", "amplitude=10:60:1", "--out", out}, "", out,
        dir / "stdout", err_path);
    CHECK(stopped.seconds < 3);
    REQUIRE(WIFEXITED(stopped.wstatus));
    CHECK(WEXITSTATUS(stopped.wstatus) == 128 + SIGINT);
    CHECK(read_text(err_path) ==
          "gaitlab: interrupted; the evaluations so far are in " + out + "\n");
    CHECK(read_text(out + "/evaluations.jsonl").empty());
    CHECK_FALSE(std::filesystem::exists(out + "/sweep.csv"));
    CHECK_FALSE(std::filesystem::exists(out + "/best.json"));
}
