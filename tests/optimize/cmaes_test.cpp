// CMA-ES on the analytic functions: the budgets docs/optimization.md states, for seeds 1 to 5
// (the comments give the worst value measured over seeds 1 to 10).
#include <catch2/catch.hpp>

#include "test_functions.h"

using namespace gaitlab::optimize;
using namespace gaitlab::optimize::testing;

namespace {
double best_of(const Function& f, int n, double lo, double hi, int generations, int population,
               std::uint64_t seed) {
    CmaesOptions o;
    o.population = population;
    auto m = make_cmaes(box(n, lo, hi), o, seed);
    return minimise(*m, f, generations);
}
}  // namespace

TEST_CASE("cmaes: sphere in 2 and 10 dimensions with the default population") {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        // 2-D: lambda 6, 60 generations (360 evaluations), worst 1.6e-10
        CHECK(best_of(sphere, 2, -5, 5, 60, 0, seed) < 1e-8);
        // 10-D: lambda 10, 120 generations (1 200 evaluations), worst 1.6e-6
        CHECK(best_of(sphere, 10, -5, 5, 120, 0, seed) < 1e-5);
    }
}

TEST_CASE("cmaes: Rosenbrock in 2 dimensions below 1e-6 in 150 generations (900 evaluations)") {
    // worst of seeds 1-10: 1.4e-8
    for (std::uint64_t seed = 1; seed <= 5; ++seed)
        CHECK(best_of(rosenbrock, 2, -5, 5, 150, 0, seed) < 1e-6);
}

TEST_CASE("cmaes: Rosenbrock in 10 dimensions below 1e-4 in 600 generations, 4 seeds of 5") {
    // 6 000 evaluations; from 4 dimensions on Rosenbrock has a local minimum near
    // (-1, 1, ..., 1), value 3.93-3.99, which some starts end in (seed 10 of 1-10 does)
    int reached = 0;
    for (std::uint64_t seed = 1; seed <= 5; ++seed)
        reached += best_of(rosenbrock, 10, -5, 5, 600, 0, seed) < 1e-4;
    CHECK(reached >= 4);
}

TEST_CASE(
    "cmaes: Rastrigin in 2 and 5 dimensions reaches the global minimum with a large population") {
    // in [-4, 6]^n, starting from the local minimum at the centre: lambda 100 for 60
    // generations (2-D, 6 000 evaluations) and lambda 300 for 100 (5-D, 30 000): every seed of
    // 1-10 reaches 0 to rounding (with lambda 200, 5-D, one seed of 10 ends at 0.995; with the
    // default lambda 6, 2-D, most starts end in a local minimum)
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        CHECK(best_of(rastrigin, 2, -4, 6, 60, 100, seed) < 1e-6);
        CHECK(best_of(rastrigin, 5, -4, 6, 100, 300, seed) < 1e-6);
    }
}

TEST_CASE("cmaes: an optimum on the boundary is reached from inside (repair and penalty)") {
    // the sphere's minimum (1, 1, 1) lies outside [-5, 0]^3: the best point in range is the
    // corner (0, 0, 0), value 3
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        auto m = make_cmaes(box(3, -5, 0), {}, seed);
        CHECK(minimise(*m, sphere, 150) < 3 + 1e-6);
        for (double v : m->best())
            CHECK(v == Approx(0).margin(1e-3));
    }
}
