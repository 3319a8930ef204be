// gaitlab.optimize{...} from Lua (scripting/src/wrap_optimize.cpp, run by cli/optimize.cpp's
// handler), as users run it: from a script under `gaitlab run` and from the console (stdin a
// pipe) it gives `gaitlab optimize`'s result with the same seed, bit for bit; bad keys and values
// are named with the script's file and line; a table in place of a spec file is refused saying
// why; SIGINT stops it; resume = true goes on from a results folder. The console's Ctrl-C is
// tested through tmux (tests/console/console_optimize_tmux_test.sh).
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "run_gaitlab.h"

using namespace gaitlab::test;

namespace {

// quick evaluations, half a second each (GA: 5 + 3 + 3 evaluations); a third parameter, a whole
// number, for the result to hold an integer
const std::string kOffset = "offset = {1, 3, integer = true}";
const std::string kSpec =
    snake_spec(R"(duration = 0.5, method = "ga", population = 5, generations = 3)", "", kOffset);

// prints what gaitlab.optimize returned, numbers to the last bit (%a)
const std::string kPrint = R"(
local names = {}
for name in pairs(r.parameters) do names[#names + 1] = name end
table.sort(names)
for _, name in ipairs(names) do
  local v = r.parameters[name]
  print(name, math.type(v), math.type(v) == "integer" and v or string.format("%a", v))
end
print("fitness", string.format("%a", r.fitness))
print("evaluations", r.evaluations, r.method, r.generations, r.population)
print("files", r.folder, r.simulation, r.run, r.plot)
)";

// best.json without its command line (the one thing that says who ran it)
std::string without_command(const std::string& json) {
    return std::regex_replace(json, std::regex("\n *\"command\": [^\n]*"), "");
}

// a number of best.json (`"KEY": NUMBER`) as %a: the exact double it holds
std::string json_number(const std::string& json, const std::string& key) {
    std::smatch m;
    if (!std::regex_search(json, m, std::regex("\"" + key + "\": ([-0-9.eE+]+)"))) return "none";
    char text[64];
    std::snprintf(text, sizeof text, "%a", std::stod(m[1].str()));
    return text;
}

// a whole number of best.json (`"KEY": NUMBER`), as Lua prints an integer
std::string json_integer(const std::string& json, const std::string& key) {
    std::smatch m;
    if (!std::regex_search(json, m, std::regex("\"" + key + "\": ([-0-9]+)[,\n]"))) return "none";
    return m[1].str();
}

// what the script printed, as the CLI's best.json says it should be
std::string expected_print(const std::string& best, const std::string& out) {
    // the paths are absolute, for the script's own functions to find them

    return "amplitude\tfloat\t" + json_number(best, "amplitude") + "\noffset\tinteger\t" +
           json_integer(best, "offset") + "\nphase\tfloat\t" + json_number(best, "phase") +
           "\nfitness\t" + json_number(best, "fitness") + "\nevaluations\t11\tga\t3\t5\nfiles\t" +
           out + "\t" + out + "/best/best.xml\t" + out + "/run\t" + out + "/convergence.png\n";
}

}  // namespace

TEST_CASE(
    "gaitlab.optimize from a script and the console: gaitlab optimize's result, bit for bit") {
    TempDir dir("cli_optimize_lua");
    write_text(dir / "spec.lua", kSpec);
    const auto cli = run_gaitlab(
        {"optimize", "spec.lua", "--seed", "5", "--workers", "2", "--out", "cli"}, dir.str());
    INFO(cli.err);
    REQUIRE(cli.status == 0);
    const std::string best = read_text(dir / "cli/best.json");

    // from a script: one worker here (the result does not depend on the number)
    write_text(dir / "script.lua",
               "r = gaitlab.optimize{ spec = 'spec.lua', seed = 5, out = 'lua' }" + kPrint);
    const auto lua = run_gaitlab({"run", "--no-record", "script.lua"}, dir.str());
    INFO(lua.err);
    REQUIRE(lua.status == 0);
    // quiet when stderr is not a terminal: no progress line
    CHECK(lua.err.empty());
    CHECK(lua.out == expected_print(best, dir / "lua"));
    CHECK(timeless(dir / "lua/evaluations.jsonl") == timeless(dir / "cli/evaluations.jsonl"));
    CHECK(without_command(read_text(dir / "lua/best.json")) == without_command(best));
    CHECK(read_text(dir / "lua/best.json").find("\"command\": \"gaitlab.optimize{ spec = ") !=
          std::string::npos);
    // the best simulation file runs
    const auto run = run_gaitlab({"run", "--no-record", "lua/best/best.xml"}, dir.str());
    CHECK(run.status == 0);
    CHECK(run.out.rfind("snake: moved ", 0) == 0);

    // the same typed at the console (stdin a pipe: no prompts), with 2 workers and a spec in
    // another folder, relative to the console's folder
    std::filesystem::create_directories(dir / "specs");
    write_text(dir / "specs/spec.lua", kSpec);
    const auto console =
        run_gaitlab({"console", "--no-record"}, dir.str(),
                    "r = gaitlab.optimize{ spec = 'specs/spec.lua', seed = 5, workers = 2, "
                    "out = 'console' }\n" +
                        std::regex_replace(kPrint, std::regex("\n(?=.)"), " ") + "\n");
    INFO(console.err);
    REQUIRE(console.status == 0);
    CHECK(console.err.empty());
    CHECK(console.out == expected_print(best, dir / "console"));
    CHECK(timeless(dir / "console/evaluations.jsonl") == timeless(dir / "cli/evaluations.jsonl"));

    // a spec relative to the script's folder, and the method, population and generations
    // overridden as --method, --population and --generations override them
    write_text(dir / "specs/pgpe.lua",
               "r = gaitlab.optimize{ spec = 'spec.lua', method = 'pgpe', population = 4, "
               "generations = 2, out = 'pgpe' }\nprint(r.evaluations, r.method, r.population)\n");
    const auto pgpe = run_gaitlab({"run", "--no-record", "specs/pgpe.lua"}, dir.str());
    INFO(pgpe.err);
    REQUIRE(pgpe.status == 0);
    CHECK(pgpe.out == "8\tpgpe\t4\n");
    const auto pgpe_cli = run_gaitlab({"optimize", "spec.lua", "--method", "pgpe", "--population",
                                       "4", "--generations", "2", "--out", "pgpe_cli"},
                                      dir.str());
    REQUIRE(pgpe_cli.status == 0);
    CHECK(timeless(dir / "pgpe/evaluations.jsonl") == timeless(dir / "pgpe_cli/evaluations.jsonl"));

    // resume = true on a finished run writes its results again, the same
    write_text(
        dir / "resume.lua",
        "r = gaitlab.optimize{ spec = 'spec.lua', seed = 5, out = 'lua', resume = true }" + kPrint);
    const auto resumed = run_gaitlab({"run", "--no-record", "resume.lua"}, dir.str());
    INFO(resumed.err);
    REQUIRE(resumed.status == 0);
    CHECK(resumed.out == expected_print(best, dir / "lua"));
    // ... and refuses other options, as --resume does
    write_text(dir / "resume_other.lua",
               "gaitlab.optimize{ spec = 'spec.lua', seed = 6, out = 'lua', resume = true }\n");
    const auto other = run_gaitlab({"run", "--no-record", "resume_other.lua"}, dir.str());
    CHECK(other.status == 1);
    CHECK(other.err.find("gaitlab: resume_other.lua:1: --resume: --seed 6 differs from the run in "
                         "lua (--seed 5)") == 0);

    // without out: a new folder runs/optimize-SPEC-DATE-TIME, never an earlier run's: the
    // folders of the next seconds are taken, so the run gets one with -2
    const std::time_t now = std::time(nullptr);
    for (int k = 0; k < 5; ++k) {
        const std::time_t t = now + k;
        std::tm tm{};
        localtime_r(&t, &tm);
        char stamp[32];
        std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
        std::filesystem::create_directories(dir / ("runs/optimize-spec-" + std::string(stamp)));
    }
    write_text(dir / "taken.lua",
               "local a = gaitlab.optimize{ spec = 'spec.lua', generations = 1 }\n"
               "print(a.folder:match('/runs/optimize%-spec%-%d+%-%d+%-2$') ~= nil)\n");
    const auto taken = run_gaitlab({"run", "--no-record", "taken.lua"}, dir.str());
    INFO(taken.err);
    CHECK(taken.status == 0);
    CHECK(taken.out == "true\n");
}

TEST_CASE("gaitlab.optimize: bad keys and values are named with the script's file and line") {
    TempDir dir("cli_optimize_lua_bad");
    write_text(dir / "spec.lua", kSpec);
    // each call on its own line, through a Lua function so that the error has its line
    const std::vector<std::string> calls = {
        "{ spec = 'spec.lua', generation = 3 }",
        "{ spec = 'spec.lua', generations = 0 }",
        "{ spec = 'spec.lua', population = 2.5 }",
        "{ spec = 'spec.lua', workers = 2000 }",
        "{ spec = 'spec.lua', workers = '2' }",
        "{ spec = 'spec.lua', seed = -1 }",
        "{ spec = 'spec.lua', seed = 'x' }",
        "{ spec = 'spec.lua', method = 'sga' }",
        "{ spec = 'spec.lua', resume = true }",
        "{ spec = 'spec.lua', resume = 'yes' }",
        "{ spec = 'spec.lua', out = '' }",
        "{ generations = 3 }",
        "{ spec = { parameters = { a = {0, 1} }, build = function() end } }",
        "{ spec = 'none.lua', out = 'none' }",
        "'spec.lua'",
    };
    std::string script;
    for (const std::string& c : calls)
        script += "print(select(2, pcall(function() return gaitlab.optimize" + c + " end)))\n";
    write_text(dir / "bad.lua", script);
    const auto r = run_gaitlab({"run", "--no-record", "bad.lua"}, dir.str());
    INFO(r.err);
    REQUIRE(r.status == 0);
    const std::string arg = "bad argument #1 to 'optimize' (";
    const std::vector<std::string> expected = {
        "bad.lua:1: " + arg + "unknown key 'generation'; did you mean 'generations'?)",
        "bad.lua:2: " + arg +
            "field 'generations': a whole number from 1 to 1000000000 expected (got '0'))",
        "bad.lua:3: " + arg +
            "field 'population': a whole number from 1 to 1000000000 expected (got '2.5'))",
        "bad.lua:4: " + arg +
            "field 'workers': a whole number from 1 to 1024 expected (got '2000'))",
        "bad.lua:5: " + arg + "field 'workers': integer expected, got string)",
        "bad.lua:6: " + arg +
            "field 'seed': a whole number from 0 to 18446744073709551615 expected (got '-1'))",
        "bad.lua:7: " + arg +
            "field 'seed': a whole number from 0 to 18446744073709551615 expected (got 'x'))",
        "bad.lua:8: " + arg + "field 'method': unknown method 'sga' (expected ga, cmaes or pgpe))",
        "bad.lua:9: " + arg +
            "field 'resume': out = DIR expected (the results folder of the run to resume))",
        "bad.lua:10: " + arg + "field 'resume': boolean expected, got string)",
        "bad.lua:11: " + arg + "field 'out': a folder expected, got \"\")",
        "bad.lua:12: " + arg + "field 'spec': a spec file expected (spec = \"SPEC.lua\"), got nil)",
        "bad.lua:13: " + arg +
            "field 'spec': a spec file expected (spec = \"SPEC.lua\"), got a table: each worker "
            "loads the spec file into a Lua state of its own, and the functions of a table "
            "cannot move between Lua states (put the table in a file that returns it))",
        "bad.lua:14: none.lua: no such file (an optimization spec, FILE.lua, expected)",
        "bad.lua:15: " + arg + "table expected, got string)",
    };
    const std::vector<std::string> got = lines(r.out);
    REQUIRE(got.size() == expected.size());
    for (size_t i = 0; i < expected.size(); ++i)
        CHECK(got[i] == expected[i]);
    // nothing was made
    CHECK_FALSE(std::filesystem::exists(dir / "none"));
    CHECK_FALSE(std::filesystem::exists(dir / "runs"));

    // unprotected, `gaitlab run` ends with the message and status 1
    write_text(dir / "stops.lua",
               "local x = 1\ngaitlab.optimize{ spec = 'spec.lua', workers = 0 }\n");
    const auto stops = run_gaitlab({"run", "--no-record", "stops.lua"}, dir.str());
    CHECK(stops.status == 1);
    CHECK(stops.err == "gaitlab: stops.lua:2: " + arg +
                           "field 'workers': a whole number from 1 to 1024 expected (got '0'))\n");
    // every evaluation failing: an error saying so, the evaluations kept
    write_text(dir / "fails.lua",
               "return { parameters = { a = {0, 1} }, fitness = 'speed', duration = 1,\n"
               "  build = function(p) error('cannot build') end, method = 'ga', population = 4,\n"
               "  generations = 1 }\n");
    write_text(dir / "all_fail.lua", "gaitlab.optimize{ spec = 'fails.lua', out = 'fails' }\n");
    const auto fails = run_gaitlab({"run", "--no-record", "all_fail.lua"}, dir.str());
    CHECK(fails.status == 1);
    CHECK(fails.err ==
          "gaitlab: all_fail.lua:1: gaitlab.optimize: every evaluation failed (see "
          "fails/evaluations.jsonl)\n");
    CHECK(lines(read_text(dir / "fails/evaluations.jsonl")).size() == 4);
}

TEST_CASE("gaitlab.optimize: SIGINT stops the evaluations under way and the script") {
    TempDir dir("cli_optimize_lua_signal");
    // long evaluations: a generation takes seconds, so the signal comes during one
    write_text(dir / "long.lua",
               snake_spec(R"(duration = 30, method = "ga", population = 5, generations = 50)", "",
                          kOffset));
    write_text(dir / "script.lua",
               "gaitlab.optimize{ spec = 'long.lua', out = 'out', population = 4 }\n"
               "print('went on')\n");
    const std::string out = dir / "out";
    const std::string err_path = dir / "err", out_path = dir / "stdout";
    const auto stopped = interrupt_while_evaluating({"run", "--no-record", "script.lua"}, dir.str(),
                                                    out, out_path, err_path);
    // the evaluations under way stop at once, not after their 30 simulated seconds
    CHECK(stopped.seconds < 3);
    REQUIRE(WIFEXITED(stopped.wstatus));
    CHECK(WEXITSTATUS(stopped.wstatus) == 128 + SIGINT);
    // the script stops there
    CHECK(read_text(out_path).empty());
    CHECK(
        read_text(err_path) ==
        "gaitlab: optimization interrupted: the evaluations so far are in out (go on with "
        "gaitlab.optimize{ ..., out = \"out\", resume = true })\ngaitlab: interrupted (SIGINT)\n");
    // nothing half-written: the generation under way is not in the file; the state to resume
    // from is there
    CHECK(read_text(out + "/evaluations.jsonl").empty());
    CHECK(std::filesystem::exists(out + "/state.json"));
    CHECK_FALSE(std::filesystem::exists(out + "/best.json"));
}
