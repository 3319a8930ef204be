#include "gaitlab/optimize/workers.h"

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "gaitlab/error.h"
#include "gaitlab/optimize/random.h"
#include "test_functions.h"

using namespace gaitlab::optimize;
using namespace gaitlab::optimize::testing;

namespace {
// the negated sphere after a random sleep of 0-3 ms: arrival order differs from ask order and
// from run to run; individuals with x1 > 4 throw, those with x2 > 4.5 return NaN
double slow_fitness(const std::vector<double>& x, int worker) {
    thread_local Random jitter(
        static_cast<std::uint64_t>(std::hash<std::thread::id>{}(std::this_thread::get_id())));
    std::this_thread::sleep_for(std::chrono::microseconds(jitter.below(3000)));
    if (x[0] > 4)
        throw std::runtime_error("fitness: x1 too large on worker " + std::to_string(worker));
    if (x[1] > 4.5) return std::nan("");
    return -sphere(x);
}

struct Outcome {
    std::string state;
    std::vector<double> best;
    int failures = 0;
    std::vector<int> workers_seen;
};

Outcome run(const std::string& method, int workers) {
    std::unique_ptr<Method> m;
    if (method == "ga") {
        GaOptions o;
        o.population = 16;
        m = make_ga(box(3, -5, 5), o, 99);
    } else if (method == "cmaes") {
        m = make_cmaes(box(3, -5, 5), {}, 99);
    } else {
        PgpeOptions o;
        o.population = 12;
        m = make_pgpe(box(3, -5, 5), o, 99);
    }
    WorkerPool pool(workers);
    Outcome out;
    out.workers_seen.assign(static_cast<std::size_t>(workers), 0);
    optimize(*m, pool, slow_fitness, 12, [&](const GenerationReport& r) {
        REQUIRE(r.evaluations->size() == r.individuals->size());
        for (std::size_t i = 0; i < r.evaluations->size(); ++i) {
            const Evaluation& e = (*r.evaluations)[i];
            const auto& x = (*r.individuals)[i];
            REQUIRE(e.worker >= 0);
            REQUIRE(e.worker < workers);
            ++out.workers_seen[static_cast<std::size_t>(e.worker)];
            REQUIRE(e.seconds >= 0);
            // each result belongs to its own individual, whoever finished first
            if (x[0] > 4) {
                REQUIRE(e.failed());
                REQUIRE(e.error.rfind("fitness: x1 too large on worker ", 0) == 0);
                ++out.failures;
            } else if (x[1] > 4.5) {
                REQUIRE(e.failed());
                REQUIRE(e.error == "the fitness is nan (expected a finite number)");
                ++out.failures;
            } else {
                REQUIRE(!e.failed());
                REQUIRE(e.fitness == -sphere(x));
            }
        }
    });
    out.state = m->save();
    out.best = m->best();
    return out;
}
}  // namespace

TEST_CASE("a run gives the same result with 1, 2 or 3 workers, whatever the arrival order") {
    for (const char* method : {"ga", "cmaes", "pgpe"}) {
        INFO(method);
        const Outcome one = run(method, 1);
        const Outcome two = run(method, 2);
        const Outcome three = run(method, 3);
        CHECK(one.state == two.state);
        CHECK(one.state == three.state);
        CHECK(one.best == three.best);
        CHECK(one.failures == three.failures);
        // the failing corner was reached and the run went on past it
        CHECK(one.failures > 0);
        CHECK(-sphere(one.best) > -2.0);
        // all workers took part
        for (int n : three.workers_seen)
            CHECK(n > 0);
    }
}

TEST_CASE("evaluations that throw anything are failures with a message, the pool goes on") {
    WorkerPool pool(2);
    const std::vector<std::vector<double>> xs = {{0}, {1}, {2}, {3}};
    const auto r = pool.evaluate(xs, [](const std::vector<double>& x, int) -> double {
        if (x[0] == 1) throw std::runtime_error("diverged at t = 2.5 s");
        if (x[0] == 2) throw 42;
        if (x[0] == 3) return INFINITY;
        return 7;
    });
    REQUIRE(r.size() == 4);
    CHECK(r[0].fitness == 7);
    CHECK(!r[0].failed());
    CHECK(r[1].error == "diverged at t = 2.5 s");
    CHECK(std::isnan(r[1].fitness));
    CHECK(r[2].error == "the evaluation failed (an exception that is not a std::exception)");
    CHECK(r[3].error == "the fitness is inf (expected a finite number)");
    CHECK(std::isnan(r[3].fitness));
    // the same pool evaluates the next batch
    const auto again = pool.evaluate(xs, [](const std::vector<double>& x, int) { return x[0]; });
    CHECK(again[3].fitness == 3);
    CHECK(pool.evaluate({}, [](const std::vector<double>&, int) { return 0.0; }).empty());
}

TEST_CASE("an evaluation that calls the pool again fails instead of deadlocking") {
    WorkerPool pool(2);
    const std::vector<std::vector<double>> xs = {{1}, {2}};
    const auto r = pool.evaluate(xs, [&](const std::vector<double>& x, int) {
        return pool.evaluate({x}, [](const std::vector<double>& y, int) { return y[0]; })[0]
            .fitness;
    });
    for (const Evaluation& e : r)
        CHECK(e.error == "WorkerPool::evaluate: a batch is already under way (one call at a time)");
    CHECK(pool.evaluate(xs, [](const std::vector<double>& x, int) { return x[0]; })[1].fitness ==
          2);
}

TEST_CASE("bad worker counts and generation counts are refused") {
    CHECK_THROWS_WITH(WorkerPool(0), "workers must be at least 1 (got 0)");
    WorkerPool pool(1);
    auto m = make_cmaes(box(2, 0, 1), {}, 1);
    CHECK_THROWS_WITH(optimize(
                          *m, pool, [](const std::vector<double>&, int) { return 0.0; }, -1),
                      "generations must be at least 0 (got -1)");
}
