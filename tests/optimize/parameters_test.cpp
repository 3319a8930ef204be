#include "gaitlab/optimize/parameters.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "gaitlab/error.h"

using gaitlab::Error;
using namespace gaitlab::optimize;

TEST_CASE("decode maps [0, 1] onto each range, clamps, and rounds integers") {
    const std::vector<Parameter> p = {{"amplitude", 10, 60, false}, {"modules", 2.5, 8.2, true}};
    CHECK(decode(p, {0.0, 0.0}) == std::vector<double>{10, 3});
    CHECK(decode(p, {1.0, 1.0}) == std::vector<double>{60, 8});
    CHECK(decode(p, {0.5, 0.5}) == std::vector<double>{35, 5});
    // outside [0, 1]: clamped into the range
    CHECK(decode(p, {-3.0, 7.0}) == std::vector<double>{10, 8});
    const auto u = encode(p, {35, 5});
    CHECK(u[0] == 0.5);
    CHECK(decode(p, u) == std::vector<double>{35, 5});
}

TEST_CASE("bad parameter lists are refused naming the parameter and what is expected") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH(validate_parameters({}),
                      "no parameters to optimize (expected at least one name with a range)");
    CHECK_THROWS_WITH(validate_parameters({{"a", 3, 3, false}}),
                      "parameter 'a': empty range [3, 3] (expected min < max)");
    CHECK_THROWS_WITH(validate_parameters({{"a", 5, 1, false}}),
                      "parameter 'a': inverted range [5, 1] (expected min < max)");
    CHECK_THROWS_WITH(validate_parameters({{"a", nan, 1, false}}),
                      "parameter 'a': range [nan, 1] is not finite (expected two finite numbers "
                      "min < max)");
    CHECK_THROWS_WITH(validate_parameters({{"a", 0, INFINITY, false}}),
                      "parameter 'a': range [0, inf] is not finite (expected two finite numbers "
                      "min < max)");
    CHECK_THROWS_WITH(validate_parameters({{"a", 0, 1, false}, {"a", 0, 2, false}}),
                      "parameter 'a': given twice (expected unique names)");
    CHECK_THROWS_WITH(validate_parameters({{"", 0, 1, false}}),
                      "parameter 1: empty name (expected a name)");
    CHECK_THROWS_WITH(validate_parameters({{"n", 0.2, 0.9, true}}),
                      "parameter 'n': integer range [0.2, 0.9] holds fewer than two whole numbers "
                      "(expected at least two)");
    CHECK_NOTHROW(validate_parameters({{"n", 0.2, 2.0, true}}));
    const std::vector<Parameter> p = {{"a", 0, 1, false}};
    CHECK_THROWS_WITH(encode(p, {2.0}), "parameter 'a': 2 is outside its range [0, 1]");
    CHECK_THROWS_WITH(encode(p, {nan}), "parameter 'a': nan is outside its range [0, 1]");
    CHECK_THROWS_WITH(encode(p, {0.1, 0.2}), "expected 1 parameter values, got 2");
}
