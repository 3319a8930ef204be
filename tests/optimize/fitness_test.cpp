// The fitness kinds of optimization specs (optimize/runner/src/fitness.cpp): what each
// measures, checked against the same quantity computed by a fitness function in the spec, the
// signs of turning and of directions, and bad fitness fields.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "gaitlab/error.h"
#include "gaitlab/optimize/runner.h"
#include "temp_dir.h"

using gaitlab::optimize::Evaluator;
using gaitlab::optimize::load_spec;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

// a 6-module pitch-yaw snake crawling with a sine on its pitch joints while an offset `bend`
// (deg) bends its yaw joints: it turns left (counter-clockwise) for bend > 0
std::string spec_with(const std::string& fitness, double settle = 0.5, double duration = 2) {
    return R"(return {
  parameters = { bend = {-30, 30} },
  build = function(p)
    local robot = gaitlab.robot.chain{ name = "snake", modules = 6, connection = "pitch-yaw" }
    local world = gaitlab.world{ floor = { friction = 0.8 } }
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 1,
                                                         phase = 120 })
    robot:group("yaw"):drive(gaitlab.controllers.offset{ angle = p.bend })
    return gaitlab.simulation{ world = world }
  end,
  fitness = )" +
           fitness + R"(,
  settle = )" +
           std::to_string(settle) +
           R"(,
  duration = )" +
           std::to_string(duration) +
           R"(,
}
)";
}

// a fitness function that runs the last 2 s itself (its spec settles 0 s and runs 0.5 s, the
// settling of spec_with's default): `measure` computes the fitness from `before` (the robot
// and sim before those 2 s) and `after`
std::string by_hand(const std::string& measure) {
    return spec_with(R"(function(sim, p)
    local robot = sim:robot("snake")
    local s = sim:status().robots[1]
    local before = { position = s.position, turned = s.turned }
    sim:run(2)
    s = sim:status().robots[1]
    local after = { position = s.position, turned = s.turned }
    )" + measure + "\n  end",
                     0, 0.5);
}

double evaluate(const TempDir& dir, const std::string& name, const std::string& spec, double bend) {
    write_text(dir / name, spec);
    Evaluator e(load_spec(dir / name));
    return e.evaluate({bend});
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

TEST_CASE("fitness heading: the turning rate, counter-clockwise positive") {
    TempDir dir("optimize_fitness_heading");
    const std::string heading = spec_with("\"heading\"");
    // a positive yaw bend turns the tail-first crawler clockwise, a negative one the other way
    const double plus = evaluate(dir, "h.lua", heading, 25);
    const double minus = evaluate(dir, "h.lua", heading, -25);
    const double straight = evaluate(dir, "h.lua", heading, 0);
    INFO("bend +25: " << plus << ", -25: " << minus << ", 0: " << straight << " deg/s");
    CHECK(plus < -2);
    CHECK(minus > 2);
    CHECK(std::abs(straight) < std::abs(plus) / 4);
    // robot:turned() over the same 2 s, in degrees per second, bit for bit
    CHECK(evaluate(dir, "f.lua", by_hand("return (after.turned - before.turned) / 2"), 25) == plus);
}

TEST_CASE("fitness direction: the displacement along a direction") {
    TempDir dir("optimize_fitness_direction");
    // the snake crawls tail first, along -x
    const double forward = evaluate(dir, "d.lua", spec_with("{ direction = {-1, 0} }"), 10);
    const double back = evaluate(dir, "d.lua", spec_with("{ direction = {1, 0} }"), 10);
    const double slanted = evaluate(dir, "d.lua", spec_with("{ direction = {-3, -4} }"), 10);
    CHECK(forward > 0.05);
    CHECK(back == -forward);
    const double dx =
        evaluate(dir, "f.lua", by_hand("return after.position.x - before.position.x"), 10);
    const double dy =
        evaluate(dir, "f.lua", by_hand("return after.position.y - before.position.y"), 10);
    CHECK(forward == -dx);
    // the direction is normalised: {-3, -4} is {-0.6, -0.8}
    CHECK(slanted == Approx(-0.6 * dx - 0.8 * dy).epsilon(1e-12));
}

TEST_CASE("fitness cost_of_transport: energy over weight times distance, negated") {
    TempDir dir("optimize_fitness_cot");
    const double cot = evaluate(dir, "c.lua", spec_with("\"cost_of_transport\""), 0);
    INFO("cost of transport " << -cot);
    CHECK(cot < 0);
    // the servos' |torque x velocity| summed every physics step by a fitness function
    const double energy = evaluate(dir, "f.lua",
                                   spec_with(R"(function(sim, p)
    local robot = sim:robot("snake")
    local mass = 0
    for _, b in ipairs(robot:bodies()) do mass = mass + b.mass end
    local s = sim:status().robots[1].position
    local joules = 0
    for _ = 1, 2000 do
      sim:step(1)
      for _, j in ipairs(robot:joints()) do
        joules = joules + math.abs(j.torque * math.rad(j.velocity)) * sim.dt
      end
    end
    local e = sim:status().robots[1].position
    local d = math.sqrt((e.x - s.x) ^ 2 + (e.y - s.y) ^ 2)
    return -joules / (mass * 9.81 * d)
  end)",
                                             0, 0.5),
                                   0);
    CHECK(cot == Approx(energy).epsilon(1e-9));
}

TEST_CASE("fitness: a robot that does not move has no cost of transport") {
    TempDir dir("optimize_fitness_still");
    std::string spec = spec_with("\"cost_of_transport\"");
    spec.replace(spec.find("amplitude = 40"), 14, "amplitude = 0");
    write_text(dir / "still.lua", spec);
    Evaluator e(load_spec(dir / "still.lua"));
    try {
        e.evaluate({0});
        FAIL("no error");
    } catch (const gaitlab::Error& error) {
        CHECK_THAT(error.what(),
                   Catch::StartsWith(dir / "still.lua" + ": cost_of_transport: the robot moved "));
        CHECK_THAT(error.what(), Catch::EndsWith(" m: no cost of transport"));
    }
}

TEST_CASE("fitness: bad fitness fields are refused naming the file and what is expected") {
    TempDir dir("optimize_fitness_bad");
    const std::string expected =
        " (expected \"distance\", \"speed\", \"cost_of_transport\", \"heading\", { "
        "direction = {X, Y} } or a function(sim, p))";
    struct Case {
        std::string fitness, message;
    };
    const std::vector<Case> cases = {
        {"'cost_of_transprot'",
         "unknown fitness 'cost_of_transprot'; did you mean 'cost_of_transport'?" + expected},
        {"'heding'", "unknown fitness 'heding'; did you mean 'heading'?" + expected},
        {"42", "got number" + expected},
        {"{ dirction = {1, 0} }",
         "unknown key 'dirction' in the table; did you mean 'direction'?" + expected},
        {"{ direction = {0, 0} }",
         "direction: {0, 0} has no direction (expected {X, Y} not both 0)"},
        {"{ direction = {1} }",
         "direction: a direction {X, Y} of two numbers expected, its Y is a nil"},
        {"{ direction = {1, 'x'} }",
         "direction: a direction {X, Y} of two numbers expected, its Y is a string"},
        // the message said "got table" of a table of two numbers, one of them NaN
        {"{ direction = {0/0, 1} }", "direction: X must be a finite number (got nan)"},
        {"{ direction = {1, -1/0} }", "direction: Y must be a finite number (got -inf)"},
        {"{ direction = {1, 2, 3} }", "direction: a direction {X, Y} of two numbers expected"},
        {"{ direction = 1 }", "direction: a direction {X, Y} of two numbers expected, got number"},
        {"{}", "direction: a direction {X, Y} of two numbers expected, got nil"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        const std::string file = dir / ("bad" + std::to_string(i) + ".lua");
        write_text(file, spec_with(cases[i].fitness));
        INFO(cases[i].fitness);
        CHECK(spec_error(file) == file + ": fitness: " + cases[i].message);
    }
}

namespace {

// a 3-module snake on floors of the friction each world gives, its amplitude jittered by
// math.random (seeded per run)
std::string averaged(const std::string& worlds, const std::string& seeds) {
    return R"(return {
  parameters = { amplitude = {10, 60} },
  build = function(p, w, seed)
    local robot = gaitlab.robot.chain{ name = "snake", modules = 3, connection = "pitch-pitch" }
    local world = gaitlab.world{ floor = { friction = w and w.friction or 0.8 } }
    if w and w.fail then error("no such floor") end
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{
      amplitude = p.amplitude + 10 * math.random(), phase = 120, frequency = 1 })
    return gaitlab.simulation{ world = world }
  end,
  fitness = "distance",
  duration = 1,
)" + (worlds.empty() ? "" : "  worlds = " + worlds + ",\n") +
           (seeds.empty() ? "" : "  seeds = " + seeds + ",\n") + "}\n";
}

}  // namespace

TEST_CASE("fitness: averaged over several worlds and seeds") {
    TempDir dir("optimize_fitness_average");
    const auto one = [&](const std::string& worlds, const std::string& seeds) {
        return evaluate(dir, "a.lua", averaged(worlds, seeds), 30);
    };
    const double slippery = one("{ { friction = 0.3 } }", "");
    const double rough = one("{ { friction = 1.0 } }", "");
    CHECK(slippery != rough);
    CHECK(one("{ { friction = 0.3 }, { friction = 1.0 } }", "") == (slippery + rough) / 2);
    // each seed its own math.random stream
    const double s1 = one("", "{ 1 }"), s2 = one("", "{ 2 }"), s3 = one("", "{ 3 }");
    CHECK(s1 != s2);
    CHECK(one("", "{ 1, 2, 3 }") == (s1 + s2 + s3) / 3);
    // worlds times seeds: every pair
    const double w1 = one("{ { friction = 0.3 } }", "{ 1, 2 }");
    const double w2 = one("{ { friction = 1.0 } }", "{ 1, 2 }");
    CHECK(one("{ { friction = 0.3 }, { friction = 1.0 } }", "{ 1, 2 }") ==
          Approx((w1 + w2) / 2).epsilon(1e-14));
    // one run that fails fails the individual, saying which
    write_text(dir / "fail.lua", averaged("{ { friction = 0.3 }, { fail = true } }", "{ 4, 5 }"));
    Evaluator e(load_spec(dir / "fail.lua"));
    CHECK_THROWS_WITH(e.evaluate({30}), dir / "fail.lua" + ":6: no such floor (world 2, seed 4)");
}

TEST_CASE("fitness: bad worlds and seeds are refused naming the file and what is expected") {
    TempDir dir("optimize_fitness_average_bad");
    struct Case {
        std::string worlds, seeds, message;
    };
    const std::string worlds = "a list of one or more worlds { W1, W2, ... } expected";
    const std::string seeds =
        "a list of one or more seeds { 1, 2, 3 } (whole numbers >= 0) expected";
    const std::vector<Case> cases = {
        {"{}", "", "worlds: " + worlds + ", got an empty table"},
        {"5", "", "worlds: " + worlds + ", got number"},
        {"{ a = 1 }", "", "worlds: " + worlds + " (a list: no other keys, no holes)"},
        {"", "{}", "seeds: " + seeds + ", got an empty table"},
        {"", "'1'", "seeds: " + seeds + ", got string"},
        {"", "{ 1, 2.5 }", "seeds[2]: a whole number >= 0 expected, got 2.5"},
        {"", "{ -1 }", "seeds[1]: a whole number >= 0 expected, got -1"},
        {"", "{ 3, 3 }", "seeds[2]: 3 is given twice (each seed once)"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        const std::string file = dir / ("bad" + std::to_string(i) + ".lua");
        write_text(file, averaged(cases[i].worlds, cases[i].seeds));
        INFO(cases[i].worlds << " " << cases[i].seeds);
        CHECK(spec_error(file) == file + ": " + cases[i].message);
    }
}
