#include "gaitlab/optimize/random.h"

#include <catch2/catch.hpp>

#include <cmath>

#include "gaitlab/error.h"

using gaitlab::optimize::Random;

TEST_CASE("the stream is mt19937_64's: the standard's 10000th number for the default seed") {
    // [rand.predef]: the 10000th consecutive invocation of a default-constructed mt19937_64
    Random r(5489u);
    std::uint64_t v = 0;
    for (int i = 0; i < 10000; ++i)
        v = r.bits();
    CHECK(v == 9981545732273789042ull);
}

TEST_CASE("uniform, below and normal have the expected moments and stay in range") {
    Random r(7);
    const int n = 200000;
    double sum = 0, sum2 = 0, usum = 0;
    std::uint64_t counts[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) {
        const double u = r.uniform();
        REQUIRE(u >= 0.0);
        REQUIRE(u < 1.0);
        usum += u;
        const auto b = r.below(3);
        REQUIRE(b < 3);
        ++counts[b];
        const double z = r.normal();
        sum += z;
        sum2 += z * z;
    }
    CHECK(usum / n == Approx(0.5).margin(0.005));
    CHECK(sum / n == Approx(0.0).margin(0.01));
    CHECK(sum2 / n == Approx(1.0).margin(0.02));
    for (auto c : counts)
        CHECK(static_cast<double>(c) / n == Approx(1.0 / 3).margin(0.01));
}

TEST_CASE("a saved state continues the same stream, a bad state is refused") {
    Random a(42);
    for (int i = 0; i < 1000; ++i)
        a.normal();
    Random b(1);
    b.set_state(a.state());
    for (int i = 0; i < 1000; ++i)
        REQUIRE(a.normal() == b.normal());
    CHECK_THROWS_WITH(b.set_state("1 2 3"),
                      "not a random stream state (expected 313 whole numbers)");
    CHECK_THROWS_WITH(b.set_state(a.state() + " 17"),
                      "not a random stream state (text after its 313 numbers)");
    CHECK_THROWS_AS(b.below(0), gaitlab::Error);
    // refused states leave the stream as it was
    Random c(42);
    for (int i = 0; i < 2000; ++i)
        c.normal();
    CHECK(b.normal() == c.normal());
}

TEST_CASE("gaitlab's distributions give fixed numbers for a seed, on every build") {
    // the first draws for seed 2024, exactly: they change only if the stream's definition does
    // (then saved optimizer states and the determinism of published runs change with it)
    Random r(2024);
    CHECK(r.uniform() == 0x1.39b1c9e957cb2p-1);
    CHECK(r.normal() == 0x1.aad7d2c419cc8p-1);
    CHECK(r.below(1000) == 714);
}
