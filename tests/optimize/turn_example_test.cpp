// examples/optimize/turn.lua: a small budget tunes the pitch-yaw snake to turn faster than the
// gait it starts from, and counter-clockwise as "heading" asks.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "gaitlab/optimize/runner.h"
#include "temp_dir.h"

using gaitlab::optimize::Evaluator;
using gaitlab::optimize::load_spec;
using gaitlab::optimize::run_optimization;
using gaitlab::optimize::RunOptions;
using gaitlab::optimize::Spec;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;

TEST_CASE("turn.lua: a small budget finds a gait that turns faster, counter-clockwise") {
    const Spec spec = load_spec(GAITLAB_SOURCE_DIR "/examples/optimize/turn.lua");
    CHECK(spec.fitness == "heading");
    REQUIRE(spec.initial == std::vector<double>{40, -5, 0.5, 120});  // amplitude, bend, ...

    Evaluator evaluator(spec);
    const double start = evaluator.evaluate(spec.initial);
    INFO("the starting gait turns " << start << " deg/s");
    // it turns counter-clockwise already, slowly
    CHECK(start > 0);

    TempDir dir("optimize_turn");
    RunOptions o;
    o.generations = 2;
    o.workers = 2;
    o.seed = 1;
    o.out = dir / "out";
    const auto r = run_optimization(spec, o);
    INFO("best " << r.best_fitness << " deg/s");
    CHECK(r.evaluations == 16);
    CHECK(r.best_fitness >= 2 * start);
    // the best measured again, in a state that ran other evaluations: the same, bit for bit
    CHECK(evaluator.evaluate(r.best) == r.best_fitness);
    // the best bends its yaw joints the counter-clockwise way (negative for this tail-first
    // crawler) and its run is recorded
    CHECK(r.best[1] < 0);
    CHECK(read_text(dir / "out/run/run.json").find("\"status\": \"finished\"") !=
          std::string::npos);
}
