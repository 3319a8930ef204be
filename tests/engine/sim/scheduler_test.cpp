// Tests for engine/include/gaitlab/scheduler.h: the order of the phases of a tick and the
// controller period.
#include "gaitlab/scheduler.h"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using namespace gaitlab;

namespace {

// records every call it receives, with the times it was given
class RecordingPhases final : public TickPhases {
  public:
    struct Call {
        std::string phase;
        double a = -1;   // time (think, record) or dt (physics)
        double b = -1;   // control_dt (think)
        long tick = -1;  // record
    };
    std::vector<Call> calls;

    void sense() override { calls.push_back({"sense"}); }
    void think(double time, double control_dt) override {
        calls.push_back({"think", time, control_dt});
    }
    void act() override { calls.push_back({"act"}); }
    void physics(double dt) override { calls.push_back({"physics", dt}); }
    void record(long tick, double time) override { calls.push_back({"record", time, -1, tick}); }

    std::vector<std::string> names() const {
        std::vector<std::string> out;
        for (const Call& c : calls)
            out.push_back(c.phase);
        return out;
    }
};

}  // namespace

TEST_CASE("one tick runs sense, think, act, physics, record in that order") {
    Scheduler s(0.001, 1);
    RecordingPhases p;
    s.tick(p);
    CHECK(p.names() == std::vector<std::string>{"sense", "think", "act", "physics", "record"});
    s.tick(p);
    CHECK(p.calls.size() == 10);
    CHECK(p.calls[5].phase == "sense");
    CHECK(p.calls[9].phase == "record");
}

TEST_CASE("think runs only on ticks where tick % control_every == 0") {
    const double dt = 0.002;
    Scheduler s(dt, 3);
    RecordingPhases p;
    std::vector<std::string> expected;
    for (long t = 0; t < 10; ++t) {
        s.tick(p);
        expected.push_back("sense");
        if (t % 3 == 0) expected.push_back("think");
        expected.insert(expected.end(), {"act", "physics", "record"});
    }
    CHECK(p.names() == expected);

    // the thinks happen at ticks 0, 3, 6, 9, see the time before the step and the control period
    std::vector<double> think_times;
    for (const auto& c : p.calls) {
        if (c.phase == "think") {
            think_times.push_back(c.a);
            CHECK(c.b == Approx(3 * dt));
        }
    }
    REQUIRE(think_times.size() == 4);
    CHECK(think_times[0] == 0.0);
    CHECK(think_times[1] == Approx(3 * dt));
    CHECK(think_times[2] == Approx(6 * dt));
    CHECK(think_times[3] == Approx(9 * dt));
}

TEST_CASE("physics gets dt and record sees the tick count and time after the step") {
    const double dt = 0.01;
    Scheduler s(dt, 30);
    RecordingPhases p;
    for (int i = 0; i < 5; ++i)
        s.tick(p);
    long expected_tick = 1;
    for (const auto& c : p.calls) {
        if (c.phase == "physics") CHECK(c.a == dt);
        if (c.phase == "record") {
            CHECK(c.tick == expected_tick);
            CHECK(c.a == static_cast<double>(expected_tick) * dt);
            ++expected_tick;
        }
    }
    CHECK(expected_tick == 6);
}

TEST_CASE("ticks and time count steps without accumulating rounding error") {
    Scheduler s(0.001, 30);
    CHECK(s.dt() == 0.001);
    CHECK(s.control_every() == 30);
    CHECK(s.ticks() == 0);
    CHECK(s.time() == 0.0);
    RecordingPhases p;
    for (int i = 0; i < 1000; ++i)
        s.tick(p);
    CHECK(s.ticks() == 1000);
    CHECK(s.time() == 1.0);  // 1000 * 0.001 rounds to exactly 1; summing 0.001 would not
    s.reset();
    CHECK(s.ticks() == 0);
    CHECK(s.time() == 0.0);

    // after a reset the controllers run again on the first tick
    p.calls.clear();
    s.tick(p);
    CHECK(p.names() == std::vector<std::string>{"sense", "think", "act", "physics", "record"});
}
