// Micro-benchmarks (Google Benchmark) of the costs below one simulation step: one control step
// of each built-in controller and of Lua controllers, one recorder row (sampling every series,
// writing it as CSV), and reading the XML files. The whole-scenario benchmarks (gaitlab against
// raw Bullet, interleaved, with callgrind) are bench_main.cpp; results of both are in
// docs/performance.md.
//
//   gaitlab_microbench [--benchmark_filter=REGEX] [--benchmark_min_time=SECONDS] ...
//
// Before timing anything the program checks that what it times works (finite targets that
// move, the Lua sine equal to the C++ one bit for bit, rows and files that read back) and
// exits 1 saying what is wrong otherwise, so a smoke run under ctest is a test.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "config_files.h"  // scripting/src: make_controller, as actuation files load controllers
#include "formats/csv.h"   // engine/src: the number format of the recorder's rows
#include "gaitlab/controller.h"
#include "gaitlab/controllers/registry.h"
#include "gaitlab/robot.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/series.h"
#include "gaitlab/simulation.h"
#include "gaitlab/xml.h"

namespace {

using gaitlab::Controller;
using gaitlab::ControllerRef;

constexpr int kJoints = 8;           // the standard 8-module snake
constexpr double kControlDt = 0.01;  // control_every = 10 at dt = 1 ms

std::string source_file(const std::string& relative) {
    return std::string(GAITLAB_SOURCE_DIR) + "/" + relative;
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read " + path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// joints that reach their targets at once: a controller reading its joints sees what it set
class TrackingJoints final : public gaitlab::JointReader {
  public:
    explicit TrackingJoints(const std::vector<double>& targets) : targets_(targets) {}
    double angle(int joint) const override { return targets_[joint]; }
    double velocity(int) const override { return 0; }
    double torque(int) const override { return 0; }

  private:
    const std::vector<double>& targets_;
};

// one group of kJoints joints driven by a controller, stepped as the scheduler steps it
class Group {
  public:
    explicit Group(std::shared_ptr<Controller> controller)
        : controller_(std::move(controller)), targets_(kJoints, 0.0), reader_(targets_) {
        for (int j = 0; j < kJoints; ++j)
            joints_.push_back(j);
        controller_->bind(kJoints);
    }
    void step() {
        gaitlab::ControlIO io(kControlDt, time_, joints_, reader_, targets_.data());
        controller_->step(io);
        time_ += kControlDt;
    }
    const std::vector<double>& targets() const { return targets_; }

  private:
    std::shared_ptr<Controller> controller_;
    std::vector<int> joints_;
    std::vector<double> targets_;
    TrackingJoints reader_;
    double time_ = 0;
};

std::shared_ptr<Controller> builtin(const std::string& name) {
    std::shared_ptr<Controller> c = gaitlab::controllers::make_builtin(name);
    if (!c) throw std::runtime_error("no built-in controller '" + name + "'");
    return c;
}

ControllerRef lua_ref(ControllerRef::Kind kind, const std::string& name) {
    ControllerRef ref;
    ref.kind = kind;
    ref.name = name;
    ref.source = "gaitlab_microbench";
    return ref;
}

// the Lua controllers timed: a controller file and the templates
struct LuaCase {
    const char* label;
    ControllerRef::Kind kind;
    std::string name;
};

std::vector<LuaCase> lua_cases() {
    return {
        {"my_sine.lua", ControllerRef::Kind::file, source_file("examples/controllers/my_sine.lua")},
        {"template sine", ControllerRef::Kind::template_, "sine"},
        {"template cpg_chain", ControllerRef::Kind::template_, "cpg_chain"}};
}

// a 16-module pitch-pitch snake with a sensor of each kind on every module, driven by a sine:
// what a recorder row samples
std::unique_ptr<gaitlab::Simulation> recorded_scene() {
    gaitlab::ChainSpec chain;
    chain.name = "snake";
    chain.modules = 16;
    gaitlab::PlacedRobot robot{gaitlab::make_chain(chain), {}, {}};
    for (int m = 0; m < chain.modules; ++m) {
        for (gaitlab::SensorKind kind :
             {gaitlab::SensorKind::imu, gaitlab::SensorKind::contact, gaitlab::SensorKind::range}) {
            gaitlab::SensorSpec s;
            s.kind = kind;
            s.module = m;
            robot.robot.sensors.push_back(s);
        }
        gaitlab::SensorSpec j;
        j.kind = gaitlab::SensorKind::joint;
        j.joint = m;
        robot.robot.sensors.push_back(j);
    }
    robot.actuation.push_back({gaitlab::select_joints(robot.robot, "pitch"), builtin("sine")});
    gaitlab::WorldSpec world;
    world.robots.push_back(robot);
    auto sim = std::make_unique<gaitlab::Simulation>(world);
    sim->run(1);  // moving, with contacts
    return sim;
}

// a robot file written body by body and joint by joint (no <chain> shorthand), with sensors
std::string long_robot_file() {
    gaitlab::ChainSpec chain;
    chain.name = "snake";
    chain.modules = 16;
    chain.connection = gaitlab::Connection::pitch_yaw;
    gaitlab::RobotSpec robot = gaitlab::make_chain(chain);
    robot.chain.reset();
    for (int m = 0; m < chain.modules; ++m) {
        gaitlab::SensorSpec s;
        s.module = m;
        robot.sensors.push_back(s);
    }
    return gaitlab::format_robot(robot);
}

// ---- the checks: what is timed works ----

void check(bool ok, const std::string& what) {
    if (!ok) throw std::runtime_error(what);
}

void check_all() {
    for (const std::string& name : gaitlab::controllers::builtin_names()) {
        Group g(builtin(name));
        for (int i = 0; i < 200; ++i)
            g.step();
        for (double t : g.targets())
            check(std::isfinite(t), name + " set a target that is not finite");
    }
    // the sine's first joint moves (the built-ins above may rest at 0, e.g. offset)
    Group sine(builtin("sine"));
    sine.step();
    const double first = sine.targets()[0];
    for (int i = 0; i < 30; ++i)
        sine.step();
    check(sine.targets()[0] != first, "the sine's targets do not move");

    // my_sine.lua and the built-in sine with the same parameters set the same targets, bit for bit
    gaitlab::scripting::LuaHost host;
    Group lua(gaitlab::scripting::make_controller(
        host.state(),
        lua_ref(ControllerRef::Kind::file, source_file("examples/controllers/my_sine.lua"))));
    Group cpp(builtin("sine"));
    for (int i = 0; i < 500; ++i) {
        lua.step();
        cpp.step();
    }
    check(lua.targets() == cpp.targets(), "my_sine.lua and the built-in sine disagree");
    for (const LuaCase& c : lua_cases()) {
        Group g(gaitlab::scripting::make_controller(host.state(), lua_ref(c.kind, c.name)));
        for (int i = 0; i < 200; ++i)
            g.step();
        for (double t : g.targets())
            check(std::isfinite(t), std::string(c.label) + ": target not finite");
    }

    // a recorder row: every series, and the CSV numbers read back to the same doubles
    auto sim = recorded_scene();
    gaitlab::SeriesSet set(*sim);
    check(set.size() > 200,
          "the recorded scene has only " + std::to_string(set.size()) + " series");
    std::vector<double> values(set.size());
    set.sample(*sim, values.data());
    std::string row;
    for (double v : values) {
        gaitlab::formats::append_number(row, v);
        row += ',';
    }
    std::vector<std::string> fields;
    row.pop_back();
    check(gaitlab::formats::split_line(row, fields) && fields.size() == values.size(),
          "a CSV row does not split into its fields");
    for (size_t i = 0; i < values.size(); ++i) {
        double back = 0;
        check(gaitlab::formats::parse_number(fields[i], back),
              "CSV field '" + fields[i] + "' is no number");
        check(back == values[i] || (std::isnan(back) && std::isnan(values[i])),
              "CSV field '" + fields[i] + "' does not read back");
    }

    // the XML files parse, and a long robot file reads back to what wrote it
    const std::string text = long_robot_file();
    check(gaitlab::format_robot(gaitlab::parse_robot(text, "long.robot.xml")) == text,
          "a robot file does not read back to itself");
    check(gaitlab::parse_robot(read_text(source_file("examples/walk/snake.robot.xml")), "snake")
                  .joints.size() == kJoints,
          "examples/walk/snake.robot.xml is not an 8-module robot");
}

// ---- the benchmarks ----

void bm_controller(benchmark::State& state, std::shared_ptr<Controller> controller) {
    Group g(std::move(controller));
    for (auto _ : state) {
        g.step();
        benchmark::DoNotOptimize(g.targets().data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * kJoints);  // joints per second
}

void bm_lua_controller(benchmark::State& state, const LuaCase& c) {
    gaitlab::scripting::LuaHost host;
    bm_controller(state,
                  gaitlab::scripting::make_controller(host.state(), lua_ref(c.kind, c.name)));
}

void bm_series_sample(benchmark::State& state) {
    auto sim = recorded_scene();
    gaitlab::SeriesSet set(*sim);
    std::vector<double> values(set.size());
    for (auto _ : state) {
        set.sample(*sim, values.data());
        benchmark::DoNotOptimize(values.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long>(values.size()));
    state.SetLabel(std::to_string(values.size()) + " series");
}

void bm_csv_row(benchmark::State& state) {
    auto sim = recorded_scene();
    gaitlab::SeriesSet set(*sim);
    std::vector<double> values(set.size());
    set.sample(*sim, values.data());
    std::string row;
    size_t bytes = 0;
    for (auto _ : state) {
        row.clear();  // the recorder appends rows to a buffer that it empties at each flush
        gaitlab::formats::append_number(row, sim->time());
        for (double v : values) {
            row += ',';
            gaitlab::formats::append_number(row, v);
        }
        row += '\n';
        bytes += row.size();
        benchmark::DoNotOptimize(row.data());
    }
    state.SetBytesProcessed(static_cast<long>(bytes));
    state.SetLabel(std::to_string(values.size()) + " series");
}

void bm_recorder_row(benchmark::State& state) {
    auto sim = recorded_scene();
    gaitlab::SeriesSet set(*sim);
    std::vector<double> values(set.size());
    std::string buffer;
    for (auto _ : state) {
        set.sample(*sim, values.data());
        gaitlab::formats::append_number(buffer, sim->time());
        for (double v : values) {
            buffer += ',';
            gaitlab::formats::append_number(buffer, v);
        }
        buffer += '\n';
        if (buffer.size() > (1u << 20)) buffer.clear();  // as if flushed
    }
    state.SetLabel(std::to_string(values.size()) + " series");
}

void bm_parse(benchmark::State& state, std::string text, int kind) {
    for (auto _ : state) {
        switch (kind) {
            case 0:
                benchmark::DoNotOptimize(gaitlab::parse_robot(text, "robot.xml"));
                break;
            case 1:
                benchmark::DoNotOptimize(gaitlab::parse_actuation(text, "actuation.xml"));
                break;
            default:
                benchmark::DoNotOptimize(gaitlab::parse_environment(text, "environment.xml"));
                break;
        }
    }
    state.SetBytesProcessed(state.iterations() * static_cast<long>(text.size()));
}

void register_all() {
    for (const std::string& name : gaitlab::controllers::builtin_names()) {
        benchmark::RegisterBenchmark(
            ("controller_step/" + name).c_str(),
            [name](benchmark::State& s) { bm_controller(s, builtin(name)); });
    }
    for (const LuaCase& c : lua_cases()) {
        benchmark::RegisterBenchmark((std::string("lua_controller_step/") + c.label).c_str(),
                                     [c](benchmark::State& s) { bm_lua_controller(s, c); });
    }
    benchmark::RegisterBenchmark("recorder/series_sample", bm_series_sample);
    benchmark::RegisterBenchmark("recorder/csv_row", bm_csv_row);
    benchmark::RegisterBenchmark("recorder/row", bm_recorder_row);
    const std::string walk = source_file("examples/walk/");
    benchmark::RegisterBenchmark("xml_parse/snake.robot.xml", bm_parse,
                                 read_text(walk + "snake.robot.xml"), 0);
    benchmark::RegisterBenchmark("xml_parse/robot_16_bodies_joints_sensors", bm_parse,
                                 long_robot_file(), 0);
    benchmark::RegisterBenchmark("xml_parse/snake.actuation.xml", bm_parse,
                                 read_text(walk + "snake.actuation.xml"), 1);
    benchmark::RegisterBenchmark("xml_parse/flat.environment.xml", bm_parse,
                                 read_text(walk + "flat.environment.xml"), 2);
}

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    try {
        check_all();
        register_all();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gaitlab_microbench: %s\n", e.what());
        return 1;
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
