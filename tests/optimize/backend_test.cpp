// The thread evaluation backend (optimize/runner/src/thread_backend.cpp): results by individual
// whatever the number of workers, an evaluation that breaks its Lua state and fails does not
// fail the next individuals of its worker, and an interrupt reaches the states made after it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "gaitlab/error.h"
#include "gaitlab/optimize/backend.h"
#include "gaitlab/optimize/runner.h"
#include "temp_dir.h"

using gaitlab::optimize::Evaluation;
using gaitlab::optimize::load_spec;
using gaitlab::optimize::make_thread_backend;
using gaitlab::optimize::Spec;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

// x > 0.7 removes string.format from its Lua state and fails; the fitness of every other
// individual needs string.format
const std::string kBreaks = R"(
return {
  parameters = { x = {0, 1} },
  build = function(p)
    if p.x > 0.7 then
      string.format = nil
      error("x > 0.7 broke the state")
    end
    local robot = gaitlab.robot.chain{ name = "snake", modules = 2, connection = "pitch-pitch" }
    local world = gaitlab.world{}
    world:add(robot)
    return gaitlab.simulation{ world = world }
  end,
  fitness = function(sim, p) return tonumber(string.format("%.3f", p.x)) end,
  duration = 0.05,
}
)";

const std::vector<std::vector<double>> kXs = {{0.1}, {0.9}, {0.2}, {0.3}, {0.8}, {0.4}};

void check_results(const std::vector<Evaluation>& r, const std::string& file) {
    REQUIRE(r.size() == kXs.size());
    for (std::size_t i = 0; i < r.size(); ++i) {
        INFO("individual " << i << ": " << r[i].error);
        if (kXs[i][0] > 0.7) {
            CHECK(r[i].failed());
            CHECK(std::isnan(r[i].fitness));
            CHECK(r[i].error.find(file) != std::string::npos);
            CHECK(r[i].error.find("x > 0.7 broke the state") != std::string::npos);
        } else {
            CHECK_FALSE(r[i].failed());
            CHECK(r[i].fitness == kXs[i][0]);
        }
    }
}

}  // namespace

TEST_CASE("thread backend: a failed evaluation's broken Lua state does not reach the next") {
    TempDir dir("backend_breaks");
    write_text(dir / "breaks.lua", kBreaks);
    const Spec spec = load_spec(dir / "breaks.lua");
    for (int workers : {1, 2}) {
        INFO(workers << " workers");
        auto backend = make_thread_backend(spec, workers);
        CHECK(backend->workers() == workers);
        CHECK(backend->describe() == (workers == 1 ? "1 worker" : "2 workers"));
        std::vector<std::size_t> done;
        const auto r =
            backend->evaluate(kXs, [&](std::size_t i, const Evaluation&) { done.push_back(i); });
        check_results(r, dir / "breaks.lua");
        CHECK(done.size() == kXs.size());
        // and again in the same states: nothing of the first batch is left
        check_results(backend->evaluate(kXs), dir / "breaks.lua");
    }
}

TEST_CASE("thread backend: an interrupt fails every later evaluation, in fresh states too") {
    TempDir dir("backend_interrupt");
    write_text(dir / "breaks.lua", kBreaks);
    const Spec spec = load_spec(dir / "breaks.lua");
    auto backend = make_thread_backend(spec, 1);
    backend->interrupt(2);
    // 0.9 fails and gives the worker a fresh state: interrupted as well
    const auto r = backend->evaluate({{0.9}, {0.1}, {0.2}});
    for (const Evaluation& e : r) {
        INFO(e.error);
        CHECK(e.failed());
    }
    CHECK(r[1].error.find("interrupt") != std::string::npos);
}

TEST_CASE("thread backend: a number of workers below 1 is refused") {
    TempDir dir("backend_workers");
    write_text(dir / "breaks.lua", kBreaks);
    const Spec spec = load_spec(dir / "breaks.lua");
    CHECK_THROWS_AS(make_thread_backend(spec, 0), gaitlab::SpecError);
    CHECK_THROWS_WITH(make_thread_backend(spec, 0), Catch::Contains("--workers"));
}

// AddressSanitizer keeps freed memory in quarantine: the resident size grows by design there
#if !defined(__SANITIZE_ADDRESS__)
namespace {

// this process's resident set size, kB (Linux)
long resident_kb() {
    std::ifstream in("/proc/self/status");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    }
    return -1;
}

}  // namespace

TEST_CASE("thread backend: the resident memory stays flat over 2000 evaluations") {
    TempDir dir("backend_memory");
    write_text(dir / "short.lua", R"(
return {
  parameters = { amplitude = {10, 60}, phase = {30, 180} },
  build = function(p)
    local robot = gaitlab.robot.chain{ name = "snake", modules = 3, connection = "pitch-pitch" }
    local world = gaitlab.world{}
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = p.amplitude,
                                                         phase = p.phase })
    return gaitlab.simulation{ world = world }
  end,
  fitness = "distance",
  duration = 0.02,
}
)");
    const Spec spec = load_spec(dir / "short.lua");
    auto backend = make_thread_backend(spec, 2);
    std::vector<std::vector<double>> xs;
    for (int i = 0; i < 100; ++i)
        xs.push_back({10 + 0.5 * i, 30 + 1.5 * i});
    // the first batches warm up (allocator pools, Lua's heap, Bullet's)
    for (int b = 0; b < 2; ++b)
        backend->evaluate(xs);
    const long warm = resident_kb();
    REQUIRE(warm > 0);
    long peak = warm;
    for (int b = 0; b < 20; ++b) {
        for (const Evaluation& e : backend->evaluate(xs))
            REQUIRE_FALSE(e.failed());
        peak = std::max(peak, resident_kb());
    }
    INFO("resident after warming up " << warm << " kB, at most " << peak << " kB over 2000 "
                                      << "evaluations");
    // a leak of 1 kB per evaluation would show as 2 MB
    CHECK(peak - warm < 2048);
}
#endif
