// Tests for engine/src/sim/controller.cpp: the controller kernel (parameters, values, binding) and
// the ControlIO a controller steps through.
#include "gaitlab/controller.h"

#include <catch2/catch.hpp>

#include <cmath>

#include <vector>

#include "gaitlab/error.h"

using namespace gaitlab;
using Catch::Matchers::Equals;

namespace {

ControllerDef probe_def() {
    return ControllerDef{
        "probe",
        {{"amplitude", 40, 0, 90, "deg"}, {"gain", 1, 0, 2, ""}, {"bias", -0.5, -1, 1, "rad"}},
        {"count", "out"}};
}

// a controller that counts its steps and writes gain * (joint + 1) + bias to every joint
class Probe final : public Controller {
  public:
    Probe() : Controller(probe_def()) {}
    void step(ControlIO& io) override {
        for (int m = 0; m < io.joints(); ++m) {
            value(0)[m] += 1;
            value(1)[m] = param(1) * (m + 1) + param(2);
            io.set_target(m, value(1)[m]);
        }
    }
    int on_bind_calls = 0;
    mutable int sync_calls = 0;

  protected:
    void on_bind() override { ++on_bind_calls; }
    void sync_values() const override { ++sync_calls; }
};

class FakeReader final : public JointReader {
  public:
    double angle(int joint) const override { return 0.1 * joint; }
    double velocity(int joint) const override { return -1.0 * joint; }
    double torque(int joint) const override { return 0.01 * joint; }
};

ParamDef param_def(const char* name, double def, double lo, double hi) {
    return ParamDef{name, def, lo, hi, ""};
}

}  // namespace

TEST_CASE("a controller starts with its declared defaults, unbound") {
    Probe c;
    CHECK(c.name() == "probe");
    CHECK(c.def().params.size() == 3);
    CHECK(c.param(0) == 40);
    CHECK(c.param("gain") == 1);
    CHECK(c.param("bias") == -0.5);
    CHECK(c.find_param("gain") == 1);
    CHECK(c.find_param("nope") == -1);
    CHECK(c.find_value("count") == 0);
    CHECK(c.find_value("out") == 1);
    CHECK(c.find_value("gain") == -1);
    CHECK(c.param_version() == 0);
    CHECK(c.joints() == 0);
    CHECK_FALSE(c.bound());
    REQUIRE_THROWS_AS(c.param("nope"), SpecError);
    REQUIRE_THROWS_WITH(c.param("nope"), Equals("controller 'probe' has no parameter 'nope'"));
}

TEST_CASE("set_param checks the range and names it with the unit") {
    Probe c;
    REQUIRE_THROWS_AS(c.set_param("amplitude", 120), SpecError);
    REQUIRE_THROWS_WITH(c.set_param("amplitude", 120),
                        Equals("probe.amplitude must be in [0, 90] deg (got 120)"));
    REQUIRE_THROWS_WITH(c.set_param(0, -1),
                        Equals("probe.amplitude must be in [0, 90] deg (got -1)"));
    // no unit: no trailing space
    REQUIRE_THROWS_WITH(c.set_param("gain", 2.5), Equals("probe.gain must be in [0, 2] (got 2.5)"));
    REQUIRE_THROWS_WITH(c.set_param("bias", -1.25),
                        Equals("probe.bias must be in [-1, 1] rad (got -1.25)"));
    REQUIRE_THROWS_WITH(c.set_param("nope", 1),
                        Equals("controller 'probe' has no parameter 'nope'"));
    // a failed set changes nothing
    CHECK(c.param("amplitude") == 40);
    CHECK(c.param_version() == 0);
    // the ends of the range are allowed
    c.set_param("amplitude", 90);
    CHECK(c.param(0) == 90);
    c.set_param("amplitude", 0);
    CHECK(c.param(0) == 0);
}

TEST_CASE("param_version increases whenever a parameter changes") {
    Probe c;
    c.set_param("gain", 1);  // same value: no change
    CHECK(c.param_version() == 0);
    c.set_param("gain", 1.5);
    CHECK(c.param_version() == 1);
    c.set_param(2, 0.25);
    CHECK(c.param_version() == 2);
    c.set_param("gain", 1.5);
    CHECK(c.param_version() == 2);
    CHECK_THROWS(c.set_param("gain", 7));
    CHECK(c.param_version() == 2);
    c.set_param("gain", 0);
    CHECK(c.param_version() == 3);
}

TEST_CASE("bind sizes the values to the group and zeroes them") {
    Probe c;
    c.bind(3);
    CHECK(c.bound());
    CHECK(c.joints() == 3);
    CHECK(c.on_bind_calls == 1);
    REQUIRE(c.values(0) == std::vector<double>{0, 0, 0});
    REQUIRE(c.values(1) == std::vector<double>{0, 0, 0});
    CHECK(c.sync_calls == 2);  // values() brings them up to date first

    REQUIRE_THROWS_AS(c.bind(2), SpecError);
    REQUIRE_THROWS_WITH(c.bind(2), Equals("controller 'probe' already drives a group (create one "
                                          "controller per group)"));
    CHECK(c.joints() == 3);

    Probe d;
    REQUIRE_THROWS_WITH(d.bind(0), Equals("a controller must drive at least one joint"));
    CHECK_FALSE(d.bound());
}

TEST_CASE("step writes targets through ControlIO, reset zeroes values and keeps parameters") {
    Probe c;
    c.bind(3);
    c.set_param("gain", 2);
    const std::vector<int> joints{4, 1, 7};
    const FakeReader reader;
    std::vector<double> targets(3, -9);
    ControlIO io(0.03, 1.5, joints, reader, targets.data());
    CHECK(io.dt() == 0.03);
    CHECK(io.time() == 1.5);
    CHECK(io.joints() == 3);
    // group joint m reads the robot joint joints[m]
    CHECK(io.angle(0) == Approx(0.4));
    CHECK(io.angle(2) == Approx(0.7));
    CHECK(io.velocity(1) == -1.0);
    CHECK(io.torque(2) == Approx(0.07));

    c.step(io);
    c.step(io);
    CHECK(targets == std::vector<double>{1.5, 3.5, 5.5});
    CHECK(io.target(1) == 3.5);
    CHECK(c.values(0) == std::vector<double>{2, 2, 2});
    CHECK(c.values(1) == std::vector<double>{1.5, 3.5, 5.5});

    c.reset();
    CHECK(c.values(0) == std::vector<double>{0, 0, 0});
    CHECK(c.values(1) == std::vector<double>{0, 0, 0});
    CHECK(c.on_bind_calls == 2);
    CHECK(c.param("gain") == 2);
    CHECK(c.joints() == 3);
}

TEST_CASE("validate(ControllerDef) rejects bad definitions") {
    ControllerDef def{"c", {param_def("a", 0.5, 0, 1), param_def("b", 0, -1, 1)}, {"v"}};
    REQUIRE_NOTHROW(validate(def));

    SECTION("empty controller name") {
        def.name.clear();
        REQUIRE_THROWS_WITH(validate(def), Equals("controller name must not be empty"));
    }
    SECTION("duplicate parameter names") {
        def.params[1].name = "a";
        REQUIRE_THROWS_AS(validate(def), SpecError);
        REQUIRE_THROWS_WITH(validate(def),
                            Equals("parameter 'a' of controller 'c' is declared twice"));
    }
    SECTION("a default outside the range") {
        def.params[0].default_value = 5;
        REQUIRE_THROWS_WITH(validate(def),
                            Equals("parameter 'a' of controller 'c': default 5 is outside its "
                                   "range [0, 1]"));
    }
    SECTION("a reversed range") {
        def.params[1].min = 2;
        def.params[1].default_value = 1.5;
        REQUIRE_THROWS_WITH(validate(def),
                            Equals("parameter 'b' of controller 'c' needs a finite range with "
                                   "min <= max"));
    }
    SECTION("an empty parameter name") {
        def.params[0].name.clear();
        REQUIRE_THROWS_WITH(validate(def), Equals("parameter names must not be empty"));
    }
    SECTION("a value named like a parameter") {
        def.values.push_back("b");
        REQUIRE_THROWS_WITH(validate(def),
                            Equals("value 'b' of controller 'c' repeats a parameter or value "
                                   "name"));
    }
    SECTION("duplicate value names") {
        def.values.push_back("v");
        REQUIRE_THROWS_WITH(validate(def),
                            Equals("value 'v' of controller 'c' repeats a parameter or value "
                                   "name"));
    }
    SECTION("an empty value name") {
        def.values.push_back("");
        REQUIRE_THROWS_WITH(validate(def), Equals("value names must not be empty"));
    }
}

TEST_CASE("a controller cannot be built from an invalid definition") {
    class Bad final : public Controller {
      public:
        Bad() : Controller(ControllerDef{"bad", {{"x", 3, 0, 1, ""}}, {}}) {}
        void step(ControlIO&) override {}
    };
    REQUIRE_THROWS_WITH(Bad(), Equals("parameter 'x' of controller 'bad': default 3 is outside "
                                      "its range [0, 1]"));
}

TEST_CASE("controller, parameter and value names are valid UTF-8 without control characters",
          "[names]") {
    using Catch::Matchers::Equals;
    ControllerDef def{"osc\n", {}, {}};
    REQUIRE_THROWS_WITH(validate(def), Equals("controller name must be valid UTF-8 without "
                                              "control characters (got \"osc\\x0a\")"));
    def.name = "osc";
    def.params.push_back(ParamDef{"gain\xff", 1, 0, 2, ""});
    REQUIRE_THROWS_WITH(validate(def),
                        Equals("parameter 'gain\xff' of controller 'osc' name must be valid UTF-8 "
                               "without control characters (got \"gain\\xff\")"));
    def.params[0].name = "gain";
    def.values.push_back("t\x01");
    REQUIRE_THROWS_WITH(validate(def),
                        Equals("value 't\x01' of controller 'osc' name must be valid UTF-8 "
                               "without control characters (got \"t\\x01\")"));
    def.values[0] = "phase";
    CHECK_NOTHROW(validate(def));
}

TEST_CASE("a target that is not a finite number is refused by ControlIO", "[divergence]") {
    std::vector<int> joints{0, 1};
    struct Zero final : JointReader {
        double angle(int) const override { return 0; }
        double velocity(int) const override { return 0; }
        double torque(int) const override { return 0; }
    } reader;
    double targets[2] = {0.5, 0.5};
    ControlIO io(0.01, 0, joints, reader, targets);
    REQUIRE_THROWS_WITH(io.set_target(1, std::nan("")),
                        "joint 2 of the group: target must be a finite number (got nan)");
    REQUIRE_THROWS_AS(io.set_target(0, HUGE_VAL), SpecError);
    CHECK(targets[0] == 0.5);
    CHECK(targets[1] == 0.5);
    io.set_target(1, -1.25);
    CHECK(targets[1] == -1.25);
}
