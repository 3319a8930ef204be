// Tests for controllers/src/hindmarsh_rose.cpp: spikes per burst follow the injected current,
// inhibitory synapses make neighbours burst in alternation, and bursts become angles.
#include "gaitlab/controllers/hindmarsh_rose.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "gaitlab/error.h"
#include "rig.h"

using namespace gaitlab;
using namespace gaitlab::test;
using Catch::Matchers::Equals;
using gaitlab::controllers::HindmarshRose;

namespace {

// records each joint's burst onsets and the spike count of each finished burst
struct BurstRig : Rig {
    BurstRig(Controller& c, int n) : Rig(c, n), onsets(joints.size()), counts(joints.size()) {}
    void run(double seconds, double dt = 0.03) {
        std::vector<double> was = ctl.values(HindmarshRose::bursting);
        run_each(seconds, dt, [&](double t) {
            for (size_t m = 0; m < joints.size(); ++m) {
                const double now = ctl.values(HindmarshRose::bursting)[m];
                if (was[m] == 0 && now == 1) onsets[m].push_back(t + dt);
                if (was[m] == 1 && now == 0)
                    counts[m].push_back(ctl.values(HindmarshRose::burst_spikes)[m]);
            }
            was = ctl.values(HindmarshRose::bursting);
        });
    }
    std::vector<std::vector<double>> onsets;
    std::vector<std::vector<double>> counts;
};

}  // namespace

TEST_CASE("hindmarsh_rose declares its parameters, ranges, units and values") {
    const HindmarshRose c;
    CHECK(c.name() == "hindmarsh_rose");
    const auto& p = c.def().params;
    REQUIRE(p.size() == 9);
    const char* names[] = {"amplitude", "offset",    "current",   "slow_rate", "time_scale",
                           "synapse",   "burst_gap", "smoothing", "seed"};
    const double defaults[] = {40, 0, 3, 0.005, 200, 0, 30, 0.1, 1};
    const char* units[] = {"deg", "deg", "", "", "1/s", "", "", "s", ""};
    for (int i = 0; i < 9; ++i) {
        CAPTURE(i);
        CHECK(c.find_param(names[i]) == i);
        CHECK(p[i].default_value == defaults[i]);
        CHECK(p[i].unit == units[i]);
    }
    const char* values[] = {"x", "z", "bursting", "burst_spikes", "angle"};
    for (int k = 0; k < 5; ++k)
        CHECK(c.find_value(values[k]) == k);
    HindmarshRose d;
    REQUIRE_THROWS_WITH(d.set_param("time_scale", 0),
                        Equals("hindmarsh_rose.time_scale must be in [1, 1000] 1/s (got 0)"));
}

TEST_CASE("a hindmarsh_rose neuron fires more spikes per burst for a larger current") {
    struct Case {
        double current, spikes;
    };
    const Case k = GENERATE(Case{2, 3}, Case{3, 5});
    const double dt = GENERATE(0.01, 0.03, 0.1);
    CAPTURE(k.current, dt);
    HindmarshRose c;
    c.set_param("current", k.current);
    BurstRig rig(c, 1);
    rig.run(4, dt);  // past the first, longer burst
    const size_t skip = rig.counts[0].size();
    rig.run(12, dt);
    const std::vector<double> counts(rig.counts[0].begin() + static_cast<long>(skip),
                                     rig.counts[0].end());
    CAPTURE(counts);
    REQUIRE(counts.size() >= 8);
    for (double n : counts)
        CHECK(n == k.spikes);
}

TEST_CASE("a hindmarsh_rose neuron's output follows its bursts") {
    HindmarshRose c;
    c.set_param("offset", 10);
    BurstRig rig(c, 1);
    CHECK(c.values(HindmarshRose::angle)[0] == -30);  // at rest: offset - amplitude
    double lo = 1e9, hi = -1e9;
    bool rose_in_burst = false;
    for (int k = 0; k < 300; ++k) {
        const double before = c.values(HindmarshRose::angle)[0];
        const bool was_on = c.values(HindmarshRose::bursting)[0] == 1;
        rig.run(0.03);
        const double now = c.values(HindmarshRose::angle)[0];
        CHECK(std::abs(rig.targets[0] - now * 3.14159265358979323846 / 180) < 1e-12);
        lo = std::min(lo, now);
        hi = std::max(hi, now);
        const bool on = c.values(HindmarshRose::bursting)[0] == 1;
        // towards +amplitude while bursting, back while resting (steps that switch are mixed)
        if (on == was_on) CHECK((on ? now >= before : now <= before));
        rose_in_burst = rose_in_burst || (on && now > before);
    }
    CHECK(rose_in_burst);
    CHECK(lo >= -30);
    CHECK(hi <= 50);
    CHECK(hi - lo > 60);  // the smoothing leaves most of the swing
}

TEST_CASE("inhibitory synapses make neighbouring hindmarsh_rose neurons burst in turn") {
    HindmarshRose c;
    c.set_param("synapse", 0.5);
    BurstRig rig(c, 2);
    rig.run(20);
    const auto& a = rig.onsets[0];
    const auto& b = rig.onsets[1];
    REQUIRE(a.size() >= 10);
    REQUIRE(b.size() >= 10);
    const double period = (a.back() - a[a.size() - 6]) / 5;
    // neuron 2's last onset falls half a period from neuron 1's
    double lag = std::fmod(b.back() - a.back(), period);
    if (lag < 0) lag += period;
    CAPTURE(period, lag);
    CHECK(lag / period == Approx(0.5).margin(0.1));
}

TEST_CASE("hindmarsh_rose's reset restarts it bit for bit") {
    HindmarshRose c;
    c.set_param("synapse", 0.5);
    BurstRig rig(c, 3);
    rig.run(2);
    const std::vector<double> first = rig.targets;
    c.reset();
    rig.run(2);
    CHECK(rig.targets == first);
}
