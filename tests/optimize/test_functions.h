// Analytic test functions for the optimization methods, as fitness to maximise (the negated
// function, whose maximum is 0), and a loop that runs a method on one of them.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "gaitlab/optimize/method.h"

namespace gaitlab::optimize::testing {

using Function = std::function<double(const std::vector<double>&)>;

/// sum (x_i - 1)^2: one minimum, 0 at (1, ..., 1) (off the ranges' centre on purpose).
inline double sphere(const std::vector<double>& x) {
    double s = 0;
    for (double v : x)
        s += (v - 1) * (v - 1);
    return s;
}

/// sum 100 (x_{i+1} - x_i^2)^2 + (1 - x_i)^2: a curved valley, 0 at (1, ..., 1).
inline double rosenbrock(const std::vector<double>& x) {
    double s = 0;
    for (std::size_t i = 0; i + 1 < x.size(); ++i)
        s += 100 * (x[i + 1] - x[i] * x[i]) * (x[i + 1] - x[i] * x[i]) + (1 - x[i]) * (1 - x[i]);
    return s;
}

/// 10 n + sum x_i^2 - 10 cos(2 pi x_i): a grid of local minima (one near every whole point),
/// the global one 0 at the origin. The tests search [-4, 6]^n, whose centre (1, ..., 1), where
/// CMA-ES and PGPE start, is a local minimum, value n.
inline double rastrigin(const std::vector<double>& x) {
    double s = 10.0 * static_cast<double>(x.size());
    for (double v : x)
        s += v * v - 10 * std::cos(2 * M_PI * v);
    return s;
}

/// `n` parameters x1..xn, each in [lo, hi].
inline std::vector<Parameter> box(int n, double lo, double hi) {
    std::vector<Parameter> p;
    for (int i = 0; i < n; ++i)
        p.push_back({"x" + std::to_string(i + 1), lo, hi, false});
    return p;
}

/// Runs `generations` generations of `method` on the negated `f`; returns the best value of f.
inline double minimise(Method& method, const Function& f, int generations) {
    for (int g = 0; g < generations; ++g) {
        const auto& xs = method.ask();
        std::vector<double> fitness;
        for (const auto& x : xs)
            fitness.push_back(-f(x));
        method.tell(fitness);
    }
    return -method.best_fitness();
}

}  // namespace gaitlab::optimize::testing
