// Replaying events (engine/src/record/replay.cpp): changes from outside the script are applied
// again at their ticks, the script's own changes are checked, and the data comes out bit for bit.
#include <catch2/catch.hpp>

#include "engine/sim_support.h"
#include "gaitlab/recorder.h"
#include "gaitlab/replay.h"
#include "gaitlab/run_data.h"
#include "temp_dir.h"

using namespace gaitlab;
using gaitlab::test::TempDir;

namespace {

// "the script": a snake whose amplitude the script changes at 0.5 s; `outside` (if set) is
// called before every tick, as a console or viewer would be
void script(const std::string& dir, const std::function<void(Simulation&)>& outside,
            const std::vector<Event>* replay_events = nullptr, long stop_tick = -1,
            std::string* divergence = nullptr, double script_amplitude = 30) {
    Simulation sim(test::chain_world(6, Connection::pitch_pitch));
    auto ctl = test::sine(40, 0.5, 120);
    test::drive(sim, "pitch", ctl);
    RecordOptions o;
    o.dir = dir;
    Recorder rec(sim, o);
    std::unique_ptr<EventReplay> replay;
    if (replay_events) {
        replay = std::make_unique<EventReplay>(sim, *replay_events, nullptr, stop_tick);
    }
    if (outside) sim.add_pre_tick(outside);
    try {
        sim.run(0.5);
        ctl->set_param("amplitude", script_amplitude);
        sim.run(1.0);
    } catch (const ReplayEnd&) {
    }
    if (replay) {
        replay->apply_due();
        if (divergence) *divergence = replay->divergence();
    }
    rec.close();
}

}  // namespace

TEST_CASE("a run with a change from outside the script replays bit for bit", "[replay]") {
    TempDir tmp("replay_engine");
    // the original: a viewer sets the frequency at tick 800, a console resets nothing
    script(tmp / "run", [](Simulation& s) {
        if (s.ticks() == 800) s.controller(0).set_param("frequency", 0.8, Origin::viewer);
    });
    RunData run(tmp / "run");
    const std::vector<Event> events = run.events();
    REQUIRE(events.size() == 2);
    CHECK(events[0].origin == Origin::script);
    CHECK(events[1].origin == Origin::viewer);
    CHECK(events[1].tick == 800);

    // replayed: the script runs again, the viewer's change comes from the recording
    std::string divergence = "?";
    script(tmp / "replay", nullptr, &events, -1, &divergence);
    CHECK(divergence.empty());
    const Comparison c = compare(run, RunData(tmp / "replay"));
    CHECK(c.difference.empty());
    CHECK(c.identical);
    CHECK(c.rows == 51);

    // without the viewer's change the data differs: the comparison can fail
    script(tmp / "plain", nullptr);
    const Comparison d = compare(run, RunData(tmp / "plain"));
    CHECK_FALSE(d.identical);
    CHECK_THAT(d.difference, Catch::StartsWith("first difference at t = 0.81 s"));

    // a script that changes something else is caught at the event
    script(tmp / "other", nullptr, &events, -1, &divergence, 35);
    CHECK(divergence ==
          "the replay made sine.amplitude = 35 (script, tick 500) where the run made "
          "sine.amplitude = 30 (script, tick 500)");
}

TEST_CASE("a replay of a run cut short stops at its last row", "[replay]") {
    TempDir tmp("replay_stop");
    script(tmp / "run", nullptr);
    RunData run(tmp / "run");
    std::string divergence = "?";
    script(tmp / "replay", nullptr, nullptr);
    const std::vector<Event> events = run.events();
    script(tmp / "short", nullptr, &events, 900, &divergence);
    CHECK(divergence.empty());
    RunData short_run(tmp / "short");
    CHECK(short_run.get("snake.com.x").time.back() == Approx(0.9));
    CHECK(compare(short_run, run).difference == "the replay has more rows than the run (31)");
}

TEST_CASE("a replay that reaches its last tick says so once, before it stops the run", "[replay]") {
    Simulation sim(test::chain_world(2, Connection::pitch_pitch));
    EventReplay replay(sim, {}, nullptr, 100);
    int ended = 0;
    long at = -1;
    replay.on_end([&] {
        ++ended;
        at = sim.ticks();
    });
    CHECK_THROWS_AS(sim.run(1), ReplayEnd);
    CHECK(at == 100);
    CHECK(replay.ended());
    // code that catches ReplayEnd and steps again is stopped again, but told only once
    CHECK_THROWS_AS(sim.step(1), ReplayEnd);
    CHECK(ended == 1);
    CHECK(sim.ticks() == 100);
}
