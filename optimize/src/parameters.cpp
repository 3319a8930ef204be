#include "gaitlab/optimize/parameters.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "gaitlab/error.h"

namespace gaitlab::optimize {

void validate_parameters(const std::vector<Parameter>& parameters) {
    if (parameters.empty())
        throw Error("no parameters to optimize (expected at least one name with a range)");
    std::set<std::string> names;
    for (std::size_t i = 0; i < parameters.size(); ++i) {
        const Parameter& p = parameters[i];
        if (p.name.empty())
            throw Error(fmt::format("parameter {}: empty name (expected a name)", i + 1));
        if (!names.insert(p.name).second)
            throw Error(fmt::format("parameter '{}': given twice (expected unique names)", p.name));
        if (!std::isfinite(p.min) || !std::isfinite(p.max))
            throw Error(
                fmt::format("parameter '{}': range [{}, {}] is not finite (expected two "
                            "finite numbers min < max)",
                            p.name, p.min, p.max));
        if (p.min > p.max)
            throw Error(fmt::format("parameter '{}': inverted range [{}, {}] (expected min < max)",
                                    p.name, p.min, p.max));
        if (p.min == p.max)
            throw Error(fmt::format("parameter '{}': empty range [{}, {}] (expected min < max)",
                                    p.name, p.min, p.max));
        if (p.integer && std::ceil(p.min) >= std::floor(p.max))
            throw Error(
                fmt::format("parameter '{}': integer range [{}, {}] holds fewer than two "
                            "whole numbers (expected at least two)",
                            p.name, p.min, p.max));
    }
}

std::vector<double> decode(const std::vector<Parameter>& parameters, const std::vector<double>& u) {
    std::vector<double> x(parameters.size());
    for (std::size_t i = 0; i < parameters.size(); ++i) {
        const Parameter& p = parameters[i];
        double v = p.min + std::clamp(u[i], 0.0, 1.0) * (p.max - p.min);
        v = std::clamp(v, p.min, p.max);
        // the nearest whole number inside the range (the range's ends may be fractions)
        if (p.integer) v = std::clamp(std::round(v), std::ceil(p.min), std::floor(p.max));
        x[i] = v;
    }
    return x;
}

std::vector<double> encode(const std::vector<Parameter>& parameters, const std::vector<double>& x) {
    if (x.size() != parameters.size())
        throw Error(
            fmt::format("expected {} parameter values, got {}", parameters.size(), x.size()));
    std::vector<double> u(parameters.size());
    for (std::size_t i = 0; i < parameters.size(); ++i) {
        const Parameter& p = parameters[i];
        if (!(x[i] >= p.min && x[i] <= p.max))
            throw Error(fmt::format("parameter '{}': {} is outside its range [{}, {}]", p.name,
                                    x[i], p.min, p.max));
        u[i] = (x[i] - p.min) / (p.max - p.min);
    }
    return u;
}

}  // namespace gaitlab::optimize
