// The optimization runner (optimize/runner/): spec files and their bad fields, evaluations in
// a Lua state per worker, failed individuals, the results folder, and the example
// examples/optimize/snake_speed.lua beating the default sine within a small budget.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "gaitlab/error.h"
#include "gaitlab/optimize/runner.h"
#include "gaitlab/scripting/lua_host.h"
#include "temp_dir.h"

using gaitlab::optimize::Evaluator;
using gaitlab::optimize::load_spec;
using gaitlab::optimize::run_optimization;
using gaitlab::optimize::RunOptions;
using gaitlab::optimize::Spec;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

const std::string kExample = GAITLAB_SOURCE_DIR "/examples/optimize/snake_speed.lua";

// a short run of a 4-module snake: quick evaluations whose result depends on every parameter
const std::string kSmall = R"(
return {
  parameters = { amplitude = {10, 60}, frequency = {0.2, 1.5}, phase = {30, 180},
                 modules = {3, 5, integer = true} },
  build = function(p)
    local robot = gaitlab.robot.chain{ name = "snake", modules = p.modules,
                                       connection = "pitch-pitch" }
    local world = gaitlab.world{ floor = { friction = 0.8 } }
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{
      amplitude = p.amplitude, frequency = p.frequency, phase = p.phase })
    return gaitlab.simulation{ world = world }
  end,
  fitness = "distance",
  settle = 0.2,
  duration = 1,
  method = "ga",
  population = 6,
  generations = 2,
}
)";

// the lines of a file with the fields that depend on timing and workers taken out
std::vector<std::string> timeless_lines(const std::string& path) {
    std::istringstream in(read_text(path));
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) {
        const auto s = line.find(",\"seconds\":");
        REQUIRE(s != std::string::npos);
        lines.push_back(line.substr(0, s));
    }
    return lines;
}

std::string spec_error(const std::string& path) {
    try {
        load_spec(path);
    } catch (const gaitlab::Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST_CASE("snake_speed.lua: a small budget finds a faster gait than the default sine") {
    const Spec spec = load_spec(kExample);
    REQUIRE(spec.parameters.size() == 3);
    CHECK(spec.parameters[0].name == "amplitude");
    CHECK(spec.parameters[1].name == "frequency");
    CHECK(spec.parameters[2].name == "phase");
    // the search starts from the sine's defaults
    REQUIRE(spec.initial == std::vector<double>{40, 0.5, 120});
    CHECK(spec.fitness == "speed");

    Evaluator evaluator(spec);
    const double default_speed = evaluator.evaluate(spec.initial);
    CHECK(default_speed > 0);

    TempDir dir("optimize_snake");
    RunOptions o;
    o.generations = 2;
    o.workers = 2;
    o.seed = 1;
    o.out = dir / "out";
    const auto r = run_optimization(spec, o);
    INFO("default " << default_speed << " m/s, best " << r.best_fitness << " m/s");
    CHECK(r.evaluations == 16);
    // issue 13 asks for 1.5x within two minutes on 2 cores; 16 evaluations reach it here
    CHECK(r.best_fitness >= 1.5 * default_speed);
    // the best individual measured again gives its fitness, bit for bit (a Lua state that
    // already ran other evaluations)
    CHECK(evaluator.evaluate(r.best) == r.best_fitness);
    CHECK(read_text(dir / "out/best.json").find("\"fitness\": ") != std::string::npos);
}

TEST_CASE("runner: the same seed gives the same evaluations with 1 and 2 workers") {
    TempDir dir("optimize_workers");
    write_text(dir / "small.lua", kSmall);
    const Spec spec = load_spec(dir / "small.lua");
    std::vector<std::vector<std::string>> runs;
    for (int workers : {1, 2}) {
        RunOptions o;
        o.workers = workers;
        o.seed = 7;
        o.out = dir / ("w" + std::to_string(workers));
        run_optimization(spec, o);
        runs.push_back(timeless_lines(o.out + "/evaluations.jsonl"));
    }
    // generation 0: 6 random individuals; generation 1: 4 children (2 elites kept)
    REQUIRE(runs[0].size() == 10);
    CHECK(runs[0] == runs[1]);
    CHECK(runs[0][0].rfind("{\"generation\":0,\"individual\":0,\"parameters\":{\"amplitude\":",
                           0) == 0);
    // integers are written as integers
    CHECK(runs[0][0].find("\"modules\":3,") + runs[0][0].find("\"modules\":4,") +
              runs[0][0].find("\"modules\":5,") !=
          3 * std::string::npos);
    // the best individual's simulation file runs the same simulation: measured as the spec
    // measures it, it gives the best fitness
    const std::string best = dir / "w1/best/best.xml";
    REQUIRE(std::filesystem::exists(best));
    CHECK(std::filesystem::exists(dir / "w1/best/best.snake.actuation.xml"));
    gaitlab::scripting::LuaHost host;
    std::string printed;
    host.set_output([&](const std::string& text) { printed += text; });
    host.run_string("local sim = assert(gaitlab.simulation.load('" + best +
                        "'))\n"
                        "sim:run(0.2)\n"
                        "local a = sim:status().robots[1].position\n"
                        "sim:run(1)\n"
                        "local b = sim:status().robots[1].position\n"
                        "print(string.format('%.17g', math.sqrt((b.x - a.x)^2 + (b.y - a.y)^2)))",
                    "check");
    const std::string best_json = read_text(dir / "w1/best.json");
    INFO(best_json);
    const auto at = best_json.find("\"fitness\": ");
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(printed) == std::stod(best_json.substr(at + 12)));
    CHECK(best_json.find("\"simulation\": \"best/best.xml\"") != std::string::npos);

    // and a different seed gives different individuals
    RunOptions o;
    o.seed = 8;
    o.out = dir / "other";
    run_optimization(spec, o);
    CHECK(timeless_lines(o.out + "/evaluations.jsonl") != runs[0]);
}

TEST_CASE("runner: an individual whose evaluation fails is marked failed and the run goes on") {
    TempDir dir("optimize_failed");
    // x > 0.5: the fitness function raises an error; x in (0.3, 0.5]: it returns NaN; build
    // fails for x < 0.1
    write_text(dir / "failing.lua", R"(return {
  parameters = { x = {0, 1} },
  build = function(p)
    if p.x < 0.1 then error("no simulation for x = " .. p.x) end
    local robot = gaitlab.robot.chain{ name = "r", modules = 2, connection = "pitch-pitch" }
    local world = gaitlab.world{}
    world:add(robot)
    return gaitlab.simulation{ world = world }
  end,
  fitness = function(sim, p)
    if p.x > 0.5 then error("x too large") end
    if p.x > 0.3 then return 0 / 0 end
    return p.x + sim.time
  end,
  duration = 0.05,
  method = "ga", population = 12, generations = 2,
})");
    const Spec spec = load_spec(dir / "failing.lua");
    RunOptions o;
    o.workers = 2;
    o.seed = 3;
    o.out = dir / "out";
    const auto r = run_optimization(spec, o);
    REQUIRE(r.best.size() == 1);
    CHECK(r.best[0] <= 0.3);
    CHECK(r.best_fitness == Approx(r.best[0] + 0.05));
    const std::string jsonl = read_text(dir / "out/evaluations.jsonl");
    INFO(jsonl);
    // each kind of failure is there with its message naming the spec file and line
    const std::string file = dir / "failing.lua";
    CHECK(jsonl.find("\"fitness\":null") != std::string::npos);
    CHECK(jsonl.find("\"error\":\"" + file + ":11: x too large\"") != std::string::npos);
    CHECK(jsonl.find("\"error\":\"" + file +
                     ": fitness: a finite number expected as its result, got nan\"") !=
          std::string::npos);
    CHECK(jsonl.find(file + ":4: no simulation for x = ") != std::string::npos);
}

TEST_CASE("runner: os.exit in a spec fails its evaluation, and huge fitness values keep a mean") {
    // os.exit ended gaitlab optimize at once with no word; fitness values near 1e308 made the
    // generation's mean (and the convergence plot's) NaN through an infinite sum
    TempDir dir("optimize_exit");
    write_text(dir / "exit.lua", R"(return {
  parameters = { x = {0, 1} },
  build = function(p)
    local robot = gaitlab.robot.chain{ name = "r", modules = 2, connection = "pitch-pitch" }
    local world = gaitlab.world{}
    world:add(robot)
    return gaitlab.simulation{ world = world, dt = 0.01 }
  end,
  fitness = function(sim, p)
    if p.x > 0.7 then os.exit(3) end
    return p.x > 0.35 and 1e308 or -1e308
  end,
  duration = 0.05,
  method = "ga", population = 12, generations = 2,
})");
    const Spec spec = load_spec(dir / "exit.lua");
    RunOptions o;
    o.seed = 5;
    o.out = dir / "out";
    std::vector<double> means;
    const auto r = run_optimization(
        spec, o, [&](const gaitlab::optimize::Progress& p) { means.push_back(p.mean); });
    CHECK(r.best_fitness == 1e308);
    const std::string jsonl = read_text(dir / "out/evaluations.jsonl");
    CHECK(jsonl.find("\"error\":\"" + dir / "exit.lua" + ":10: os.exit ends no evaluation") !=
          std::string::npos);
    REQUIRE(means.size() == 2);
    for (const double m : means) {
        CHECK(std::isfinite(m));
        CHECK(std::abs(m) <= 1e308);
    }
    const std::string csv = read_text(dir / "out/convergence.csv");
    INFO(csv);
    CHECK(csv.find("NaN") == std::string::npos);
}

TEST_CASE("runner: a build that returns no simulation or a robot that is not there fails") {
    TempDir dir("optimize_bad_build");
    write_text(dir / "nosim.lua", R"(return {
  parameters = { x = {0, 1} },
  build = function(p) return 42 end,
  fitness = "speed", duration = 1,
})");
    Evaluator e(load_spec(dir / "nosim.lua"));
    CHECK_THROWS_WITH(e.evaluate({0.5}),
                      dir / "nosim.lua" +
                          ": build: a simulation expected as its result, got number (return "
                          "gaitlab.simulation{ ... })");
    write_text(dir / "norobot.lua", R"(return {
  parameters = { x = {0, 1} },
  build = function(p)
    local world = gaitlab.world{}
    world:add(gaitlab.robot.chain{ name = "a", modules = 2, connection = "pitch-pitch" })
    return gaitlab.simulation{ world = world }
  end,
  fitness = "distance", duration = 0.1, robot = "b",
})");
    Evaluator e2(load_spec(dir / "norobot.lua"));
    CHECK_THROWS_WITH(
        e2.evaluate({0.5}),
        dir / "norobot.lua" + ": robot: the simulation has no robot 'b' (it has 'a')");
}

TEST_CASE("runner: bad spec files are refused naming the file and the field") {
    TempDir dir("optimize_bad_spec");
    const std::string good_build =
        "build = function(p) return nil end, fitness = 'speed', duration = 1";
    struct Case {
        std::string text;
        std::string message;  // after "FILE: "
    };
    const std::vector<Case> cases = {
        {"return { parameters = { a = {0, 1} }, fitness = 'speed', duration = 1 }",
         "build: missing (a function(p) that returns a simulation expected)"},
        {"return { parameters = { a = {1, 0} }, " + good_build + " }",
         "parameters: parameter 'a': inverted range [1, 0] (expected min < max)"},
        {"return { parameters = { a = {0, 1} }, build = function() end, fitness = 'sped', "
         "duration = 1 }",
         "fitness: unknown fitness 'sped'; did you mean 'speed'? (expected \"distance\", "
         "\"speed\", \"cost_of_transport\", \"heading\", { direction = {X, Y} } or a "
         "function(sim, p))"},
        {"return { parameters = { a = {0, 1} }, build = function() end, duration = 1 }",
         "fitness: missing (expected \"distance\", \"speed\", \"cost_of_transport\", "
         "\"heading\", { direction = {X, Y} } or a function(sim, p))"},
        {"return { parameters = { a = {0, 1} }, " + good_build + ", generation = 3 }",
         "unknown field 'generation'; did you mean 'generations'? (expected parameters, build, "
         "fitness, duration, settle, robot, method, population, generations, worlds, seeds, "
         "simulation, set)"},
        {"return { parameters = { a = {0, 1} }, build = function() end, fitness = 'speed' }",
         "duration: missing (a number of seconds > 0 expected)"},
        {"return { parameters = { a = {0, 1} }, " + good_build + ", settle = -1 }",
         "settle: a number of seconds in [0, 1e6] expected, got -1"},
        // no simulation runs 1e300 s: every evaluation failed instead of the spec refused
        {"return { parameters = { a = {0, 1} }, build = function() end, fitness = 'speed', "
         "duration = 1e300 }",
         "duration: a number of seconds in (0, 1e6] expected, got 1e+300"},
        {"return { parameters = {}, " + good_build + " }",
         "parameters: at least one parameter expected ({ amplitude = {10, 60} })"},
        {"return { parameters = { a = {0, 1, initial = 2} }, " + good_build + " }",
         "parameters.a.initial: 2 is outside the range [0, 1]"},
        {"return { parameters = { a = {0, 'x'} }, " + good_build + " }",
         "parameters.a: MAX of the range {MIN, MAX}: a number expected, got string"},
        {"return { parameters = { a = {0, 1, integr = true} }, " + good_build + " }",
         "parameters.a: unknown key 'integr' (expected {MIN, MAX}, integer = true, initial = "
         "VALUE)"},
        {"return { parameters = { a = 5 }, " + good_build + " }",
         "parameters.a: a range {MIN, MAX} expected (optionally integer = true, initial = "
         "VALUE), got number"},
        {"return { parameters = { a = {0, 1} }, " + good_build + ", method = 'pgp' }",
         "method: unknown method 'pgp'; did you mean 'pgpe'? (expected \"ga\", \"cmaes\" or "
         "\"pgpe\")"},
        {"return { parameters = { a = {0, 1} }, " + good_build + ", population = 0 }",
         "population: a whole number >= 1 expected, got 0"},
        // Lua's 0/0 has its sign bit set: it was shown as "-nan"
        {"return { parameters = { a = {0, 1} }, " + good_build + ", generations = 0/0 }",
         "generations: a whole number >= 1 expected, got nan"},
        {"return 42",
         "the spec file must return a table { parameters =, build =, fitness =, "
         "duration = ... } (got number)"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        const std::string file = dir / ("spec" + std::to_string(i) + ".lua");
        write_text(file, cases[i].text);
        INFO(cases[i].text);
        CHECK(spec_error(file) == file + ": " + cases[i].message);
    }
    // an integer range without two whole numbers in it
    write_text(dir / "int.lua",
               "return { parameters = { n = {0.2, 0.8, integer = true} }, " + good_build + " }");
    CHECK(spec_error(dir / "int.lua").rfind(dir / "int.lua" + ": parameters: parameter 'n': ", 0) ==
          0);
    // a syntax error names the line; a file that is not there says so
    write_text(dir / "syntax.lua", "return {\n  parameters = { a = {0, 1} \n  build = 3 }\n");
    CHECK(spec_error(dir / "syntax.lua").find("syntax.lua:3:") != std::string::npos);
    CHECK(spec_error(dir / "none.lua") ==
          dir / "none.lua" + ": no such file (an optimization spec, FILE.lua, expected)");
}

TEST_CASE("runner: a results folder that holds files is refused and kept as it was") {
    TempDir dir("optimize_out");
    write_text(dir / "small.lua", kSmall);
    const Spec spec = load_spec(dir / "small.lua");
    std::filesystem::create_directories(dir / "out");
    write_text(dir / "out/evaluations.jsonl", "an earlier run\n");
    RunOptions o;
    o.out = dir / "out";
    CHECK_THROWS_WITH(run_optimization(spec, o),
                      "--out " + o.out +
                          ": the folder exists and is not empty (an earlier run's results are "
                          "kept: choose another folder)");
    CHECK(read_text(dir / "out/evaluations.jsonl") == "an earlier run\n");
    o.workers = 0;
    o.out = dir / "new";
    CHECK_THROWS_WITH(run_optimization(spec, o), "--workers: a whole number >= 1 expected, got 0");
    o.workers = 1;
    o.method = "gaa";
    CHECK_THROWS_WITH(run_optimization(spec, o),
                      "--method: unknown method 'gaa'; did you mean 'ga'? (expected \"ga\", "
                      "\"cmaes\" or \"pgpe\")");
}
