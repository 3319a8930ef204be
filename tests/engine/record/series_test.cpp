// Series (engine/src/record/series.cpp): names from robot and controller labels, units, selections
// by kind and pattern with suggestions, and every controller parameter and value as a series.
#include <catch2/catch.hpp>

#include <fmt/format.h>

#include "engine/sim_support.h"
#include "gaitlab/controllers/hopf.h"
#include "gaitlab/error.h"
#include "gaitlab/recorder.h"
#include "gaitlab/run_data.h"
#include "gaitlab/series.h"
#include "temp_dir.h"

using namespace gaitlab;
using gaitlab::test::TempDir;

namespace {

Simulation snake_sim(int modules = 4) {
    return Simulation(test::chain_world(modules, Connection::pitch_pitch));
}

}  // namespace

TEST_CASE("series are named by robot and controller label, joints from 1", "[recorder]") {
    Simulation sim(test::chain_world(3, Connection::pitch_yaw));
    test::drive(sim, "all", test::sine(10, 0.5, 0));
    test::drive(sim, "pitch", test::sine(10, 0.5, 0));
    const SeriesSet set(sim);
    std::vector<std::string> names;
    for (const SeriesInfo& s : set.series())
        names.push_back(s.name);
    auto has = [&](const std::string& n) {
        return std::find(names.begin(), names.end(), n) != names.end();
    };
    for (const char* n :
         {"snake.com.x",       "snake.com.vz",    "snake.tail.x",     "snake.segment2.qw",
          "snake.head.qz",     "snake.angle[1]",  "snake.angle[3]",   "snake.target[2]",
          "snake.velocity[3]", "snake.torque[1]", "snake.power[2]",   "snake.energy[3]",
          "snake.power",       "snake.energy",    "sine.amplitude",   "sine.phase0",
          "sine.angle[3]",     "sine.time[1]",    "sine_2.amplitude", "sine_2.angle[2]"})
        CHECK(has(n));
    CHECK_FALSE(has("snake.angle[4]"));
    CHECK_FALSE(has("sine_2.angle[3]"));  // the pitch group of a 3-joint pitch-yaw has 2 joints
    const SeriesInfo& a = set.series()[static_cast<size_t>(set.find("snake.angle[3]"))];
    CHECK(a.kind == SeriesKind::robot);
    CHECK(a.value == "angle");
    CHECK(a.joint == 3);
    CHECK(a.unit == "deg");
    const SeriesInfo& b = set.series()[static_cast<size_t>(set.find("snake.head.qz"))];
    CHECK(b.body == "head");
    CHECK(b.value == "qz");
    const SeriesInfo& c = set.series()[static_cast<size_t>(set.find("sine_2.amplitude"))];
    CHECK(c.kind == SeriesKind::controller);
    CHECK(c.source == "sine_2");
    CHECK(c.unit == "deg");
    CHECK(sim.drive_label(0) == "sine");
    CHECK(sim.drive_label(1) == "sine_2");
    CHECK(sim.robot_label(0) == "snake");
}

TEST_CASE("labels stay unique among robots and controllers", "[recorder]") {
    WorldSpec w = test::chain_world(2, Connection::pitch_pitch);
    w.robots.push_back(w.robots[0]);
    w.robots[1].pose.position = {0, 1, 0};
    Simulation sim(w);
    CHECK(sim.robot_label(0) == "snake");
    CHECK(sim.robot_label(1) == "snake_2");
    // a controller named like a robot gets a suffix too; its own name stays
    struct Snake final : Controller {
        Snake() : Controller(ControllerDef{"snake", {{"k", 1, 0, 2, ""}}, {}}) {}
        void step(ControlIO&) override {}
    };
    sim.add_drive(1, Drive{{0}, std::make_shared<controllers::Sine>()});
    sim.add_drive(0, Drive{{1}, std::make_shared<Snake>()});
    CHECK(sim.drive_label(0) == "sine");
    CHECK(sim.drive_label(1) == "snake_3");
    CHECK(sim.controller(1).name() == "snake");
    const SeriesSet set(sim, {"snake_2.angle[*]", "sine.*", "snake_3.*"});
    CHECK(set.size() == 2 + 5 + 2 + 1);
    CHECK(set.series()[0].name == "snake_2.angle[1]");
}

TEST_CASE("selections pick kinds and name patterns, a bad one suggests names", "[recorder]") {
    Simulation sim = snake_sim();
    test::drive(sim, "pitch", test::sine(10, 0.5, 0));
    CHECK(SeriesSet(sim, {"controller"}).size() == 5 + 2 * 4);
    CHECK(SeriesSet(sim, {"snake.com.*"}).size() == 6);
    CHECK(SeriesSet(sim, {"snake.angle[?]", "snake.angle[1]"}).size() == 4);
    CHECK(SeriesSet(sim, {"sensor"}).size() == 0);
    try {
        SeriesSet bad(sim, {"snake.angel[2]"});
        FAIL("no error");
    } catch (const SpecError& e) {
        CHECK(std::string(e.what()) ==
              "no series matches 'snake.angel[2]'; did you mean 'snake.angle[2]', "
              "'snake.angle[1]' or 'snake.angle[3]'?");
    }
    CHECK(glob_match("a*c", "abbc"));
    CHECK(glob_match("*", ""));
    CHECK(glob_match("s?ne.*", "sine.x"));
    CHECK_FALSE(glob_match("a*c", "abcd"));
    CHECK(glob_match("snake.angle[1]", "snake.angle[1]"));
}

TEST_CASE("every parameter and per-joint value of a controller is a series", "[recorder]") {
    TempDir tmp("recorder_hopf");
    Simulation sim(test::chain_world(5, Connection::pitch_pitch));
    auto hopf = std::make_shared<controllers::Hopf>();
    test::drive(sim, "pitch", hopf);
    RecordOptions o;
    o.dir = tmp / "run";
    o.series = {"hopf.*"};
    Recorder rec(sim, o);
    sim.run(0.6);  // the last row is taken after the last control step's values
    rec.close();
    RunData run(tmp / "run");
    CHECK(run.series().size() == 7 + 3 * 5);
    const SeriesInfo& x3 = run.find("hopf.x[3]");
    CHECK(x3.kind == SeriesKind::controller);
    CHECK(x3.source == "hopf");
    CHECK(x3.value == "x");
    CHECK(x3.joint == 3);
    CHECK(run.find("hopf.convergence").unit == "1/s");
    for (const char* v : {"x", "y", "angle"}) {
        const std::vector<double>& now = hopf->values(hopf->find_value(v));
        for (int m = 1; m <= 5; ++m) {
            const SeriesData d = run.get(fmt::format("hopf.{}[{}]", v, m));
            CHECK(d.values.back() == now[static_cast<size_t>(m - 1)]);
        }
    }
    CHECK(run.get("hopf.frequency").values.back() == 0.5);
}

TEST_CASE("energy reads the same in every recording of a simulation, from time 0", "[recorder]") {
    // the energy is integrated by the simulation from time 0, not by the series from when they
    // start: a set made at 0, one made later, a clone's and one after a reset agree bit for bit
    auto make = [] {
        auto sim = std::make_unique<Simulation>(test::chain_world(4, Connection::pitch_pitch));
        test::drive(*sim, "all", test::sine(40, 0.5, 120));
        return sim;
    };
    // a set sampled at the end, ticked every tick as the recorder does
    struct Watched {
        SeriesSet set;
        explicit Watched(Simulation& sim) : set(sim, {"snake.energy*", "snake.power*"}) {
            sim.add_observer([this](const Simulation& s) { set.tick(s); });
        }
        std::vector<double> now(const Simulation& sim) {
            std::vector<double> out(set.size());
            set.sample(sim, out.data());
            return out;
        }
    };
    const std::unique_ptr<Simulation> from0_ptr = make();
    Simulation& from0 = *from0_ptr;
    Watched w0(from0);
    from0.run(1.5);
    const std::vector<double> expected = w0.now(from0);
    const int total = w0.set.find("snake.energy");
    REQUIRE(total >= 0);
    CHECK(expected[static_cast<size_t>(total)] > 0.01);

    const std::unique_ptr<Simulation> late_ptr = make();
    Simulation& late = *late_ptr;
    late.run(1.2);
    Watched wl(late);
    late.run(0.3);
    CHECK(wl.now(late) == expected);

    const std::unique_ptr<Simulation> original_ptr = make();
    Simulation& original = *original_ptr;
    original.run(1.5);
    const std::unique_ptr<Simulation> copy = original.clone();
    Watched wc(*copy);
    CHECK(wc.now(*copy) == expected);
    copy->run(0.5);
    original.run(0.5);
    Watched wo(original);
    CHECK(wc.now(*copy) == wo.now(original));

    const std::unique_ptr<Simulation> again_ptr = make();
    Simulation& again = *again_ptr;
    again.run(0.7);
    again.reset();
    std::vector<double> zero(4, 0.0);
    again.joint_energies(0, zero.data());
    CHECK(zero == std::vector<double>(4, 0.0));
    Watched wr(again);
    again.run(1.5);
    CHECK(wr.now(again) == expected);

    std::vector<double> joules(4, 0.0);
    from0.joint_energies(0, joules.data());
    CHECK(joules[2] == expected[static_cast<size_t>(w0.set.find("snake.energy[3]"))]);
}
