// Tests for controllers/src/registry.cpp: the built-in controllers by name.
#include "gaitlab/controllers/registry.h"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace gaitlab;

TEST_CASE("builtin_names lists the built-in controllers, sorted") {
    const auto names = controllers::builtin_names();
    REQUIRE_FALSE(names.empty());
    CHECK(std::is_sorted(names.begin(), names.end()));
    CHECK(std::find(names.begin(), names.end(), "sine") != names.end());
}

TEST_CASE("make_builtin makes a fresh, unbound controller with defaults, or nullptr") {
    for (const std::string& name : controllers::builtin_names()) {
        CAPTURE(name);
        const auto a = controllers::make_builtin(name);
        const auto b = controllers::make_builtin(name);
        REQUIRE(a);
        REQUIRE(b);
        CHECK(a != b);
        CHECK(a->name() == name);
        CHECK_FALSE(a->bound());
        for (int i = 0; i < static_cast<int>(a->def().params.size()); ++i) {
            CHECK(a->param(i) == a->def().params[i].default_value);
        }
    }
    CHECK(controllers::make_builtin("sine")->param("amplitude") == 40);
    CHECK(controllers::make_builtin("nope") == nullptr);
    CHECK(controllers::make_builtin("") == nullptr);
    CHECK(controllers::make_builtin("Sine") == nullptr);
}
