// What every method guarantees: determinism for a seed, failures ranked last, resuming from a
// saved state, integer parameters, and clear errors for bad use and bad states.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "gaitlab/error.h"
#include "gaitlab/optimize/method.h"
#include "test_functions.h"

using gaitlab::Error;
using namespace gaitlab::optimize;
using namespace gaitlab::optimize::testing;

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();

std::unique_ptr<Method> make(const std::string& method, std::vector<Parameter> p,
                             std::uint64_t seed) {
    if (method == "ga") {
        GaOptions o;
        o.population = 12;
        return make_ga(std::move(p), o, seed);
    }
    if (method == "cmaes") return make_cmaes(std::move(p), CmaesOptions{}, seed);
    PgpeOptions o;
    o.population = 10;
    return make_pgpe(std::move(p), o, seed);
}

// every individual asked and the best found, over `generations` on the negated Rosenbrock
std::vector<std::vector<double>> trace(Method& m, int generations) {
    std::vector<std::vector<double>> all;
    for (int g = 0; g < generations; ++g) {
        const auto xs = m.ask();
        std::vector<double> f;
        for (const auto& x : xs) {
            all.push_back(x);
            f.push_back(-rosenbrock(x));
        }
        m.tell(f);
    }
    all.push_back(m.best());
    return all;
}
}  // namespace

TEST_CASE("each method is deterministic for a seed, bit for bit, and seeds differ") {
    for (const char* name : {"ga", "cmaes", "pgpe"}) {
        INFO(name);
        auto a = make(name, box(4, -2, 3), 11);
        auto b = make(name, box(4, -2, 3), 11);
        auto c = make(name, box(4, -2, 3), 12);
        const auto ta = trace(*a, 25);
        CHECK(ta == trace(*b, 25));  // operator== on doubles: bit-identical (no NaN here)
        CHECK(ta != trace(*c, 25));
        CHECK(a->save() == b->save());
        CHECK(a->generation() == 25);
        CHECK(a->name() == name);
        // the best is one of the asked points, and as good as every asked point
        double best = -INFINITY;
        for (std::size_t i = 0; i + 1 < ta.size(); ++i)
            best = std::max(best, -rosenbrock(ta[i]));
        CHECK(a->best_fitness() == best);
        CHECK(-rosenbrock(a->best()) == best);
    }
}

TEST_CASE("ask() gives points inside the ranges, integers whole, the same until tell()") {
    for (const char* name : {"ga", "cmaes", "pgpe"}) {
        INFO(name);
        const std::vector<Parameter> p = {{"a", -1, 1, false}, {"n", 1, 9, true}};
        auto m = make(name, p, 3);
        for (int g = 0; g < 20; ++g) {
            const auto xs = m->ask();
            CHECK(m->ask() == xs);
            std::vector<double> f;
            for (const auto& x : xs) {
                REQUIRE(x[0] >= -1);
                REQUIRE(x[0] <= 1);
                REQUIRE(x[1] >= 1);
                REQUIRE(x[1] <= 9);
                REQUIRE(x[1] == std::round(x[1]));
                // the best n is 7: every method must find an integer optimum too
                f.push_back(-(x[1] - 7) * (x[1] - 7) - x[0] * x[0]);
            }
            m->tell(f);
        }
        CHECK(m->best()[1] == 7);
    }
}

TEST_CASE("failed individuals (NaN, infinite) rank last and never become the best") {
    for (const char* name : {"ga", "cmaes", "pgpe"}) {
        INFO(name);
        auto m = make(name, box(2, -5, 5), 5);
        // the region x1 > 0 fails; the optimum (1, 1) of the sphere lies in it, so the best
        // the method may report has x1 <= 0, and failures must not drag the search
        for (int g = 0; g < 80; ++g) {
            const auto xs = m->ask();
            std::vector<double> f;
            for (std::size_t i = 0; i < xs.size(); ++i) {
                const auto& x = xs[i];
                f.push_back(x[0] > 0 ? (i % 2 ? kNaN : INFINITY) : -sphere(x));
            }
            m->tell(f);
        }
        REQUIRE(std::isfinite(m->best_fitness()));
        CHECK(m->best()[0] <= 0);
        // it still converges on the boundary of the failing region: (0, 1), sphere = 1 (the
        // start, the centre (0, 0), has 2)
        CHECK(-m->best_fitness() < 1.1);
        CHECK(m->evaluations() > 0);
    }
}

TEST_CASE("a generation where every individual fails is survived") {
    for (const char* name : {"ga", "cmaes", "pgpe"}) {
        INFO(name);
        auto m = make(name, box(3, -5, 5), 8);
        m->tell(std::vector<double>(m->ask().size(), kNaN));
        CHECK(std::isnan(m->best_fitness()));
        CHECK(m->best().empty());
        CHECK(minimise(*m, sphere, 30) < 3);
    }
}

TEST_CASE("a run resumed from its saved state ends exactly like an uninterrupted one") {
    for (const char* name : {"ga", "cmaes", "pgpe"}) {
        INFO(name);
        auto whole = make(name, box(5, -5, 5), 21);
        const auto expected = trace(*whole, 40);

        // interrupted after 15 generations, and again between an ask() and its tell()
        auto first = make(name, box(5, -5, 5), 21);
        auto part = trace(*first, 15);
        part.pop_back();
        auto second = load_method(first->save(), "state.json");
        const auto pending = second->ask();
        auto third = load_method(second->save(), "state.json");
        CHECK(third->ask() == pending);
        auto rest = trace(*third, 25);
        part.insert(part.end(), rest.begin(), rest.end());
        CHECK(part == expected);
        CHECK(third->save() == whole->save());
        CHECK(third->evaluations() == whole->evaluations());
        CHECK(third->generation() == 40);
    }
}

TEST_CASE("tell() with the wrong number of values or before ask() is refused") {
    for (const char* name : {"ga", "cmaes", "pgpe"}) {
        INFO(name);
        auto m = make(name, box(3, 0, 1), 1);
        CHECK_THROWS_WITH(m->tell({1.0}), std::string(name) +
                                              ": tell() before ask() (generation 0 has no "
                                              "individuals yet)");
        const std::size_t n = m->ask().size();
        CHECK_THROWS_WITH(m->tell(std::vector<double>(n - 1, 0.0)),
                          std::string(name) + ": expected " + std::to_string(n) +
                              " fitness values (one per individual of generation 0, in ask "
                              "order), got " +
                              std::to_string(n - 1));
        // the refused tell() changed nothing: the generation is still pending
        CHECK(m->generation() == 0);
        CHECK_NOTHROW(m->tell(std::vector<double>(n, 0.0)));
    }
}

TEST_CASE("bad options and ranges are refused naming what is expected") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    GaOptions ga;
    ga.population = 3;
    CHECK_THROWS_WITH(make_ga(box(2, 0, 1), ga, 1),
                      "ga: population 3 is too small (expected at least 4)");
    ga = {};
    ga.elites = 49;
    CHECK_THROWS_WITH(make_ga(box(2, 0, 1), ga, 1),
                      "ga: elites 49 must be in [0, population - 2 = 48]");
    ga = {};
    ga.tournament = 1;
    CHECK_THROWS_WITH(make_ga(box(2, 0, 1), ga, 1),
                      "ga: tournament 1 must be in [2, population = 50]");
    ga = {};
    ga.crossover_rate = nan;
    CHECK_THROWS_WITH(make_ga(box(2, 0, 1), ga, 1), "ga: crossover_rate nan must be in [0, 1]");
    ga = {};
    ga.initial = {0.5};
    CHECK_THROWS_WITH(make_ga(box(2, 0, 1), ga, 1),
                      "ga: initial has 1 values (expected one per parameter: 2)");
    ga.initial = {0.5, 3};
    CHECK_THROWS_WITH(make_ga(box(2, 0, 1), ga, 1),
                      "ga: initial point: parameter 'x2': 3 is outside its range [0, 1]");

    CmaesOptions cma;
    cma.population = 3;
    CHECK_THROWS_WITH(
        make_cmaes(box(2, 0, 1), cma, 1),
        "cmaes: population 3 is too small (expected at least 4, or 0 for the default)");
    cma = {};
    cma.sigma = 0;
    CHECK_THROWS_WITH(make_cmaes(box(2, 0, 1), cma, 1),
                      "cmaes: sigma 0 must be in (0, 1] (range widths)");

    PgpeOptions pgpe;
    pgpe.population = 7;
    CHECK_THROWS_WITH(make_pgpe(box(2, 0, 1), pgpe, 1),
                      "pgpe: population 7 must be even and at least 2 (symmetric pairs mean +- "
                      "epsilon)");
    pgpe = {};
    pgpe.baseline_decay = 1;
    CHECK_THROWS_WITH(make_pgpe(box(2, 0, 1), pgpe, 1), "pgpe: baseline_decay 1 must be in [0, 1)");

    // ranges: every method checks them first
    CHECK_THROWS_WITH(make_cmaes({{"a", 1, 0, false}}, {}, 1),
                      "parameter 'a': inverted range [1, 0] (expected min < max)");
    CHECK_THROWS_WITH(make_pgpe({{"a", 1, 1, false}}, {}, 1),
                      "parameter 'a': empty range [1, 1] (expected min < max)");
    CHECK_THROWS_WITH(make_ga({{"a", nan, 1, false}}, {}, 1),
                      "parameter 'a': range [nan, 1] is not finite (expected two finite numbers "
                      "min < max)");
    CHECK_THROWS_WITH(make_ga({}, {}, 1),
                      "no parameters to optimize (expected at least one name with a range)");
}

TEST_CASE("a state that is not one is refused naming its source and what is wrong") {
    auto m = make("cmaes", box(2, 0, 1), 1);
    minimise(*m, sphere, 3);
    const std::string good = m->save();
    auto replace = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        const auto at = s.find(from);
        REQUIRE(at != std::string::npos);
        return s.replace(at, from.size(), to);
    };
    CHECK_THROWS_WITH(load_method("", "run/state.json"),
                      Catch::StartsWith("run/state.json: not an optimizer state: "));
    CHECK_THROWS_WITH(load_method("{}", "s.json"),
                      "s.json: not an optimizer state: 'format': missing");
    CHECK_THROWS_WITH(load_method(replace("\"cmaes\"", "\"sa\""), "s.json"),
                      "s.json: not an optimizer state: 'method': \"sa\" is not one (expected "
                      "\"ga\", \"cmaes\" or \"pgpe\")");
    CHECK_THROWS_WITH(load_method(replace("\"version\": 1", "\"version\": 9"), "s.json"),
                      "s.json: not an optimizer state: 'version': 9 is not known (expected 1)");
    CHECK_THROWS_WITH(load_method(replace("\"sigma\": 0.3", "\"sigma\": -1"), "s.json"),
                      "s.json: not an optimizer state: cmaes: sigma -1 must be in (0, 1] (range "
                      "widths)");
    CHECK_THROWS_WITH(load_method(replace("\"min\": 0.0", "\"min\": 2.0"), "s.json"),
                      "s.json: not an optimizer state: parameter 'x1': inverted range [2, 1] "
                      "(expected min < max)");
    CHECK_THROWS_WITH(load_method(replace("\"generation\": 3", "\"generation\": -3"), "s.json"),
                      "s.json: not an optimizer state: 'generation': expected a whole number in "
                      "[0, 2147483647], got -3");
    CHECK_THROWS_WITH(load_method(replace("\"random\": \"", "\"random\": \"x"), "s.json"),
                      "s.json: not an optimizer state: 'random': not a random stream state "
                      "(expected 313 whole numbers)");
    // a truncated file (a run killed while writing it would leave one without atomic writes)
    CHECK_THROWS_WITH(load_method(good.substr(0, good.size() / 2), "s.json"),
                      Catch::StartsWith("s.json: not an optimizer state: "));
    CHECK_NOTHROW(load_method(good, "s.json"));
}
