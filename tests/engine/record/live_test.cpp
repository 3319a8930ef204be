// Live buffers (engine/src/record/live.cpp): the latest samples of chosen series, adjustable
// sampling, refresh and size, read from another thread while the simulation runs.
#include <catch2/catch.hpp>

#include <atomic>
#include <thread>

#include "engine/sim_support.h"
#include "gaitlab/error.h"
#include "gaitlab/live.h"

using namespace gaitlab;

TEST_CASE("live buffers hold the newest samples, oldest first", "[live]") {
    Simulation sim(test::chain_world(4, Connection::pitch_pitch));
    test::drive(sim, "pitch", test::sine(40, 0.5, 120));
    LiveOptions o;
    o.series = {"snake.angle[2]", "sine.angle[2]"};
    o.sample_every = 10;
    o.refresh_seconds = 0;
    o.size = 4;
    LiveBuffers live(sim, o);
    sim.run(0.1);
    LiveSnapshot s = live.snapshot();
    REQUIRE(s.time.size() == 4);
    CHECK(s.names == std::vector<std::string>{"snake.angle[2]", "sine.angle[2]"});
    CHECK(s.time[0] == Approx(0.07));
    CHECK(s.time[3] == Approx(0.1));
    CHECK(s.values[0][3] == Approx(rad_to_deg(sim.joint(0, 1).angle)));
    CHECK(s.version == 10);

    // growing keeps what there is, shrinking keeps the newest
    live.set_size(6);
    sim.run(0.02);
    s = live.snapshot({"sine.angle[2]"});
    REQUIRE(s.time.size() == 6);
    CHECK(s.time[0] == Approx(0.07));
    CHECK(s.time[5] == Approx(0.12));
    live.set_size(2);
    s = live.snapshot();
    REQUIRE(s.time.size() == 2);
    CHECK(s.time[1] == Approx(0.12));
    live.set_sample_every(30);
    sim.run(0.1);
    s = live.snapshot();
    CHECK(s.time[0] == Approx(0.18));
    CHECK(s.time[1] == Approx(0.21));

    // a reset empties them: time starts again
    sim.reset();
    s = live.snapshot();
    REQUIRE(s.time.size() == 1);
    CHECK(s.time[0] == 0);

    CHECK_THROWS_WITH(live.set_size(0), "size must be in [1, 10000000] samples (got 0)");
    CHECK_THROWS_WITH(live.set_sample_every(0),
                      "sample_every must be in [1, 1000000000] ticks (got 0)");
    CHECK_THROWS_WITH(live.set_refresh_seconds(-1),
                      "refresh must be a non-negative number of seconds (got -1)");
    CHECK_THROWS_WITH(live.snapshot({"snake.angle[9]"}),
                      "the live buffers keep no series 'snake.angle[9]'; did you mean "
                      "'snake.angle[2]' or 'sine.angle[2]'?");
}

TEST_CASE("a refresh period batches publications", "[live]") {
    Simulation sim(test::chain_world(2, Connection::pitch_pitch));
    LiveOptions o;
    o.series = {"snake.com.x"};
    o.sample_every = 1;
    o.refresh_seconds = 3600;  // one publication, then none within the test
    o.size = 100;
    LiveBuffers live(sim, o);
    sim.run(0.05);
    CHECK(live.version() == 1);
    CHECK(live.snapshot().time.size() == 1);
    live.publish();  // the samples taken since
    CHECK(live.version() == 2);
    CHECK(live.snapshot().time.size() == 50);
}

TEST_CASE("another thread reads consistent snapshots while the simulation runs", "[live]") {
    Simulation sim(test::chain_world(6, Connection::pitch_pitch));
    test::drive(sim, "pitch", test::sine(40, 0.5, 120));
    LiveOptions o;
    o.series = {"snake.com.x", "snake.angle[1]", "sine.time[1]"};
    o.sample_every = 1;
    o.refresh_seconds = 0;
    o.size = 50;
    LiveBuffers live(sim, o);
    std::atomic<bool> done{false};
    std::atomic<int> reads{0}, bad{0};
    std::thread reader([&] {
        std::uint64_t last = 0;
        while (!done.load()) {
            const LiveSnapshot s = live.snapshot();
            // times strictly increase by one tick, every column as long as the time column
            for (size_t i = 1; i < s.time.size(); ++i) {
                if (!(std::abs(s.time[i] - s.time[i - 1] - 0.001) < 1e-9)) ++bad;
            }
            for (const auto& v : s.values) {
                if (v.size() != s.time.size()) ++bad;
            }
            if (s.version < last) ++bad;
            last = s.version;
            // settings change from this thread too
            live.set_size(40 + static_cast<int>(reads.load() % 20));
            ++reads;
        }
    });
    sim.run(1.0);
    done = true;
    reader.join();
    CHECK(bad == 0);
    CHECK(reads > 0);
    CHECK(live.snapshot().time.back() == Approx(1.0));
}
