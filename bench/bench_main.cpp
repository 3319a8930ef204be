// gaitlab_bench: the performance and accuracy benchmarks of docs/performance.md.
//
//   gaitlab_bench overhead [--quick] [--reps R] [--seconds S]   gaitlab vs the raw Bullet loop
//   gaitlab_bench lua      [--quick] [--reps R] [--seconds S]   Lua controller vs C++ sine
//   gaitlab_bench accuracy [--quick] [--ce MS] [--jobs J]      displacement vs converged runs
//   gaitlab_bench record   [--quick] [--reps R] [--seconds S]   gaitlab with and without recording
//   gaitlab_bench memory   [--hours H] [--modules N] [--ce C]   memory over a long recorded run
//   gaitlab_bench one --impl raw|gaitlab|lua-sine|lua-controller [--conn pp|py] [--modules N]
//                     [--ce C] [--iterations I] [--dt S] [--seconds S] [--controller NAME]
//                     [--sensors none|off|on] [--record DIR]
//
// Timed runs measure the stepping loop only (the scene is built before the clock starts), as
// thread CPU time and wall time. Variants of one scenario run back to back and alternate their
// order from one repetition to the next; tables show medians. Under
// `valgrind --tool=callgrind --instr-atstart=no` only the stepping loop is counted.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif

#include <filesystem>
#include <fstream>
#include <memory>

#include "gaitlab/recorder.h"
#include "gaitlab/simulation.h"
#include "gaitlab_scene.h"
#include "raw_bullet_loop.h"
#include "scenario.h"

namespace gaitlab_bench {
namespace {

// ---------------------------------------------------------------------------------------------
// timing

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

double wall_seconds() {
    using Clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

struct Stopwatch {
    double cpu0 = thread_cpu_seconds();
    double wall0 = wall_seconds();
    double cpu() const { return thread_cpu_seconds() - cpu0; }
    double wall() const { return wall_seconds() - wall0; }
};

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t k = v.size() / 2;
    return v.size() % 2 ? v[k] : (v[k - 1] + v[k]) / 2;
}

double min_of(const std::vector<double>& v) {
    return *std::min_element(v.begin(), v.end());
}
double max_of(const std::vector<double>& v) {
    return *std::max_element(v.begin(), v.end());
}

// ---------------------------------------------------------------------------------------------
// one timed run of one implementation

enum class Impl { raw, gaitlab, lua_sine, lua_controller };

const char* to_string(Impl i) {
    switch (i) {
        case Impl::raw:
            return "raw";
        case Impl::gaitlab:
            return "gaitlab";
        case Impl::lua_sine:
            return "lua-sine";
        case Impl::lua_controller:
            return "lua-controller";
    }
    return "?";
}

Impl parse_impl(const std::string& s) {
    for (Impl i : {Impl::raw, Impl::gaitlab, Impl::lua_sine, Impl::lua_controller}) {
        if (s == to_string(i)) return i;
    }
    throw std::runtime_error("unknown --impl '" + s +
                             "' (expected raw, gaitlab, lua-sine or lua-controller)");
}

struct Sample {
    double cpu_us = 0;   // per step
    double wall_us = 0;  // per step
    Vec d;               // centre-of-mass displacement at the end, m
};

template <class Stepper>
Sample time_loop(Stepper&& step, long ticks) {
    Sample s;
    CALLGRIND_START_INSTRUMENTATION;
    const Stopwatch w;
    step(ticks);
    const double cpu = w.cpu(), wall = w.wall();
    CALLGRIND_STOP_INSTRUMENTATION;
    s.cpu_us = cpu * 1e6 / static_cast<double>(ticks);
    s.wall_us = wall * 1e6 / static_cast<double>(ticks);
    return s;
}

Vec to_vec(const gaitlab::Vec3& v) {
    return {v.x, v.y, v.z};
}

// `record_dir` non-empty (gaitlab only): every series recorded at every control tick into it,
// the last write inside the timed loop
Sample run_once(Impl impl, const Scenario& sc, const std::string& lua_file,
                const std::string& record_dir = {}) {
    const long ticks = sc.ticks();
    switch (impl) {
        case Impl::raw: {
            RawSnake snake(sc);
            Sample s = time_loop([&](long n) { snake.step(n); }, ticks);
            s.d = snake.displacement();
            return s;
        }
        case Impl::gaitlab: {
            gaitlab::Simulation sim(make_world(sc), make_options(sc));
            std::unique_ptr<gaitlab::Recorder> rec;
            if (!record_dir.empty()) {
                gaitlab::RecordOptions o;
                o.dir = record_dir;
                rec = std::make_unique<gaitlab::Recorder>(sim, o);
            }
            Sample s = time_loop(
                [&](long n) {
                    sim.step(n);
                    if (rec) rec->flush();
                },
                ticks);
            if (rec) rec->close();
            s.d = to_vec(sim.robot_displacement(0));
            return s;
        }
        case Impl::lua_sine:
        case Impl::lua_controller: {
            LuaScene scene(sc, impl == Impl::lua_sine ? std::string() : lua_file);
            Sample s = time_loop([&](long n) { scene.step(n); }, ticks);
            s.d = scene.displacement();
            return s;
        }
    }
    return {};
}

// ---------------------------------------------------------------------------------------------
// command line

struct Args {
    std::string command;
    bool quick = false;
    int reps = 0;        // 0: the command's default
    double seconds = 0;  // 0: the command's default
    int ce = 0;          // accuracy: control period in ms (default 30)
    int jobs = 0;        // accuracy: threads (default 2)
    Impl impl = Impl::gaitlab;
    Scenario one;
    std::string lua_file = default_lua_controller();
    std::string record_dir;  // one: record into this folder
    double hours = 1;        // memory: simulated hours
};

Args parse(int argc, char** argv) {
    Args a;
    if (argc < 2) throw std::runtime_error("usage: gaitlab_bench overhead|lua|accuracy|one ...");
    a.command = argv[1];
    for (int i = 2; i < argc; ++i) {
        const std::string k = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw std::runtime_error(k + " needs a value");
            return argv[++i];
        };
        if (k == "--quick") {
            a.quick = true;
        } else if (k == "--reps") {
            a.reps = std::stoi(value());
        } else if (k == "--seconds") {
            a.seconds = std::stod(value());
            a.one.seconds = a.seconds;
        } else if (k == "--ce") {
            a.ce = std::stoi(value());
            a.one.control_every = a.ce;
        } else if (k == "--jobs") {
            a.jobs = std::stoi(value());
        } else if (k == "--impl") {
            a.impl = parse_impl(value());
        } else if (k == "--conn") {
            const std::string c = value();
            if (c != "pp" && c != "py") throw std::runtime_error("--conn takes pp or py");
            a.one.pitch_yaw = c == "py";
        } else if (k == "--modules") {
            a.one.modules = std::stoi(value());
        } else if (k == "--iterations") {
            a.one.solver_iterations = std::stoi(value());
        } else if (k == "--dt") {
            a.one.dt = std::stod(value());
        } else if (k == "--controller") {
            a.one.controller = value();
        } else if (k == "--sensors") {
            a.one.sensors = value();
        } else if (k == "--lua-controller") {
            a.lua_file = value();
        } else if (k == "--record") {
            a.record_dir = value();
        } else if (k == "--hours") {
            a.hours = std::stod(value());
        } else {
            throw std::runtime_error("unknown option " + k);
        }
    }
    return a;
}

std::vector<Scenario> gait_scenarios(const std::vector<int>& control_every, double seconds) {
    std::vector<Scenario> out;
    for (int ce : control_every) {
        for (bool py : {false, true}) {
            for (int n : {8, 16, 32}) {
                Scenario s;
                s.modules = n;
                s.pitch_yaw = py;
                s.control_every = ce;
                s.seconds = seconds;
                out.push_back(s);
            }
        }
    }
    return out;
}

// Runs every implementation of `impls` on every scenario `reps` times, the implementations of a
// scenario back to back, their order rotated each repetition. Result: [scenario][impl][rep].
using Results = std::vector<std::vector<std::vector<Sample>>>;

Results interleave(const std::vector<Scenario>& scenarios, const std::vector<Impl>& impls, int reps,
                   const std::string& lua_file) {
    // warm up caches, the allocator and the Lua state's code paths
    for (Impl i : impls) {
        Scenario w = scenarios.front();
        w.seconds = 1;
        run_once(i, w, lua_file);
    }
    Results r(scenarios.size(), std::vector<std::vector<Sample>>(impls.size()));
    for (int rep = 0; rep < reps; ++rep) {
        for (size_t s = 0; s < scenarios.size(); ++s) {
            for (size_t k = 0; k < impls.size(); ++k) {
                // rotate, and reverse every other repetition: ABBA for two implementations
                size_t i = (k + static_cast<size_t>(rep / 2)) % impls.size();
                if (rep % 2) i = impls.size() - 1 - i;
                r[s][i].push_back(run_once(impls[i], scenarios[s], lua_file));
            }
        }
        std::fprintf(stderr, "  repetition %d/%d done\n", rep + 1, reps);
    }
    return r;
}

std::vector<double> field(const std::vector<Sample>& v, double Sample::*f) {
    std::vector<double> out;
    for (const Sample& s : v)
        out.push_back(s.*f);
    return out;
}

// median of the per-repetition ratios b / a, and their spread
struct Ratio {
    double median = 0, lo = 0, hi = 0;
};

Ratio paired_ratio(const std::vector<Sample>& a, const std::vector<Sample>& b, double Sample::*f) {
    std::vector<double> q;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i)
        q.push_back(b[i].*f / a[i].*f);
    return {median(q), min_of(q), max_of(q)};
}

const char* same(const Vec& a, const Vec& b) {
    if (a.x == b.x && a.y == b.y && a.z == b.z) return "identical";
    const double e = std::hypot(a.x - b.x, a.y - b.y);
    return e < 1e-6 ? "< 1 µm" : e < 1e-3 ? "< 1 mm" : "DIFFERENT";
}

double geomean(const std::vector<double>& v) {
    double s = 0;
    for (double x : v)
        s += std::log(x);
    return std::exp(s / static_cast<double>(v.size()));
}

// ---------------------------------------------------------------------------------------------
// commands

int cmd_overhead(const Args& a) {
    const int reps = a.reps ? a.reps : (a.quick ? 3 : 5);
    const double seconds = a.seconds ? a.seconds : (a.quick ? 3 : 10);
    const std::vector<Scenario> sc = gait_scenarios({10, 30}, seconds);
    const std::vector<Impl> impls = {Impl::raw, Impl::gaitlab};
    std::fprintf(stderr,
                 "overhead: %zu scenarios x %zu implementations x %d repetitions, %g s "
                 "simulated each\n",
                 sc.size(), impls.size(), reps, seconds);
    const Results r = interleave(sc, impls, reps, a.lua_file);

    std::printf(
        "\n### gaitlab (C++ API) vs the raw Bullet loop: %g simulated s, median of %d "
        "interleaved runs\n\n",
        seconds, reps);
    std::printf(
        "| scenario | raw µs/step | gaitlab µs/step | ratio (CPU) | ratio range | "
        "ratio (wall) | raw dx, dy (m) | gaitlab vs raw trajectory |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    std::vector<double> ratios;
    for (size_t s = 0; s < sc.size(); ++s) {
        const auto& raw = r[s][0];
        const auto& gl = r[s][1];
        const Ratio cpu = paired_ratio(raw, gl, &Sample::cpu_us);
        const Ratio wall = paired_ratio(raw, gl, &Sample::wall_us);
        ratios.push_back(cpu.median);
        std::printf("| %s | %.2f | %.2f | **%.3f** | %.3f–%.3f | %.3f | %+.4f, %+.4f | %s |\n",
                    sc[s].label().c_str(), median(field(raw, &Sample::cpu_us)),
                    median(field(gl, &Sample::cpu_us)), cpu.median, cpu.lo, cpu.hi, wall.median,
                    raw[0].d.x, raw[0].d.y, same(raw[0].d, gl[0].d));
    }
    std::printf("\ngeometric mean of the CPU ratios: %.3f (target ≤ 1.05)\n", geomean(ratios));
    return 0;
}

int cmd_lua(const Args& a) {
    const int reps = a.reps ? a.reps : (a.quick ? 3 : 5);
    const double seconds = a.seconds ? a.seconds : (a.quick ? 3 : 10);
    const std::vector<Scenario> sc = gait_scenarios({10}, seconds);
    const std::vector<Impl> impls = {Impl::gaitlab, Impl::lua_sine, Impl::lua_controller};
    std::fprintf(stderr,
                 "lua: %zu scenarios x %zu implementations x %d repetitions, %g s "
                 "simulated each\n",
                 sc.size(), impls.size(), reps, seconds);
    const Results r = interleave(sc, impls, reps, a.lua_file);

    std::printf(
        "\n### Lua controller (my_sine.lua) vs the C++ sine, control_every = 10: %g "
        "simulated s, median of %d interleaved runs\n\n",
        seconds, reps);
    std::printf(
        "| scenario | C++ sine, C++ API µs/step | C++ sine, Lua scene µs/step | "
        "Lua controller µs/step | Lua / C++ API (CPU) | range | Lua / C++ (wall) | "
        "Lua vs C++ trajectory |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    std::vector<double> ratios;
    for (size_t s = 0; s < sc.size(); ++s) {
        const auto& cpp = r[s][0];
        const auto& lsine = r[s][1];
        const auto& lctl = r[s][2];
        const Ratio cpu = paired_ratio(cpp, lctl, &Sample::cpu_us);
        const Ratio wall = paired_ratio(cpp, lctl, &Sample::wall_us);
        ratios.push_back(cpu.median);
        std::printf("| %s | %.2f | %.2f | %.2f | **%.3f** | %.3f–%.3f | %.3f | %s |\n",
                    sc[s].label().c_str(), median(field(cpp, &Sample::cpu_us)),
                    median(field(lsine, &Sample::cpu_us)), median(field(lctl, &Sample::cpu_us)),
                    cpu.median, cpu.lo, cpu.hi, wall.median, same(cpp[0].d, lctl[0].d));
    }
    std::printf("\ngeometric mean of the CPU ratios: %.3f (target ≤ 1.05)\n", geomean(ratios));
    return 0;
}

struct AccuracyRun {
    Vec d;
    double cpu_us = 0;
    double max_separation = 0;  // m
    double max_axis = 0;        // rad
};

AccuracyRun run_accuracy(const Scenario& sc) {
    gaitlab::Simulation sim(make_world(sc), make_options(sc));
    const int joints = sc.modules;
    const long chunk = std::max(1L, std::lround(0.01 / sc.dt));  // sample every 10 ms
    const long ticks = sc.ticks();
    AccuracyRun out;
    double cpu = 0;
    for (long done = 0; done < ticks; done += chunk) {
        const Stopwatch w;
        sim.step(std::min(chunk, ticks - done));
        cpu += w.cpu();
        for (int j = 0; j < joints; ++j) {
            const gaitlab::JointError e = sim.joint_error(0, j);
            out.max_separation = std::max(out.max_separation, e.separation);
            out.max_axis = std::max(out.max_axis, e.axis_angle);
        }
    }
    out.d = to_vec(sim.robot_displacement(0));
    out.cpu_us = cpu * 1e6 / static_cast<double>(ticks);
    return out;
}

// Runs `jobs` on `threads` threads (each job builds and steps its own simulation).
void run_parallel(std::vector<std::function<void()>>& jobs, int threads) {
    std::atomic<size_t> next{0};
    auto worker = [&] {
        for (size_t k = next++; k < jobs.size(); k = next++)
            jobs[k]();
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t)
        pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool)
        t.join();
}

int cmd_accuracy(const Args& a) {
    const double seconds = a.seconds ? a.seconds : 20;
    const int ce = a.ce ? a.ce : 30;
    std::vector<int> sizes = {8, 16, 32};
    if (a.quick) sizes = {8, 32};
    struct Variant {
        const char* name;
        int iterations;
        double dt;
        double perturbation;  // deg added to the gait amplitudes
    };
    // the first one is gaitlab's default (20 iterations, dt 1 ms), which costs are compared
    // with; the last one is the reference: 10x smaller step and more iterations
    std::vector<Variant> vs = {{"default (20 it, 1 ms)", 20, 0.001, 0},
                               {"default, amplitude +1e-6°", 20, 0.001, 1e-6},
                               {"10 it (Bullet's default)", 10, 0.001, 0},
                               {"30 it", 30, 0.001, 0},
                               {"50 it", 50, 0.001, 0},
                               {"100 it", 100, 0.001, 0},
                               {"dt 0.1 ms (10 it)", 10, 0.0001, 0},
                               {"dt 0.1 ms, 50 it (ref)", 50, 0.0001, 0}};
    if (a.quick) {
        vs = {{"default (20 it, 1 ms)", 20, 0.001, 0},
              {"default, amplitude +1e-6°", 20, 0.001, 1e-6},
              {"10 it (Bullet's default)", 10, 0.001, 0},
              {"50 it", 50, 0.001, 0},
              {"100 it", 100, 0.001, 0},
              {"dt 0.1 ms (10 it) (ref)", 10, 0.0001, 0}};
    }
    const int threads = a.jobs > 0 ? a.jobs : 2;
    std::optional<size_t> it100;
    for (size_t k = 0; k < vs.size(); ++k) {
        if (vs[k].iterations == 100 && vs[k].dt == 0.001) it100 = k;
    }

    struct Case {
        bool py;
        int n;
        std::vector<AccuracyRun> runs;
    };
    std::vector<Case> cases;
    for (bool py : {false, true}) {
        for (int n : sizes)
            cases.push_back({py, n, std::vector<AccuracyRun>(vs.size())});
    }
    // the costliest jobs first, so the two threads finish together
    std::vector<std::pair<double, std::function<void()>>> weighted;
    for (Case& c : cases) {
        for (size_t k = 0; k < vs.size(); ++k) {
            Scenario s;
            s.modules = c.n;
            s.pitch_yaw = c.py;
            s.seconds = seconds;
            s.solver_iterations = vs[k].iterations;
            s.dt = vs[k].dt;
            s.pitch_amplitude += vs[k].perturbation;
            s.yaw_amplitude += vs[k].perturbation;
            // keep the control period (ce ms) whatever the step
            s.control_every = static_cast<int>(std::lround(ce * 0.001 / vs[k].dt));
            const double weight = c.n * (s.solver_iterations + 5) / s.dt;
            AccuracyRun* out = &c.runs[k];
            weighted.emplace_back(weight, [s, out] {
                *out = run_accuracy(s);
                std::fprintf(stderr, "  %s done\n", s.label().c_str());
            });
        }
    }
    std::stable_sort(weighted.begin(), weighted.end(),
                     [](const auto& x, const auto& y) { return x.first > y.first; });
    std::vector<std::function<void()>> jobs;
    for (auto& w : weighted)
        jobs.push_back(std::move(w.second));
    std::fprintf(stderr, "accuracy: %zu runs on %d threads\n", jobs.size(), threads);
    run_parallel(jobs, threads);

    std::printf("\n### Accuracy: centre-of-mass displacement after %g s, control period %d ms\n\n",
                seconds, ce);
    std::printf(
        "Error = |d − d_ref| / |d_ref| (x and y) with d_ref = the \"%s\" run. "
        "µs/step is thread CPU time of one run (%d runs at a time), so costs are "
        "indicative; cost × compares CPU time per simulated second with the default "
        "settings. Joint error: worst pivot separation and axis misalignment over all "
        "joints, sampled every 10 ms.\n\n",
        vs.back().name, threads);
    std::printf(
        "| scenario | settings | dx (m) | dy (m) | error vs ref | error vs 100 it | "
        "µs/step | CPU s per simulated s | cost × | max separation (mm) | "
        "max axis error (°) |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const Case& c : cases) {
        auto error = [&](const Vec& d, size_t ref) {
            const Vec r = c.runs[ref].d;
            return std::hypot(d.x - r.x, d.y - r.y) / std::hypot(r.x, r.y);
        };
        auto cell = [](double err, bool is_ref) {
            char buf[32];
            if (is_ref) return std::string("(ref)");
            std::snprintf(buf, sizeof buf, err > 0.02 ? "**%.2f %%**" : "%.2f %%", err * 100);
            return std::string(buf);
        };
        const size_t last = vs.size() - 1;
        for (size_t k = 0; k < vs.size(); ++k) {
            const AccuracyRun& run = c.runs[k];
            const std::string e_ref = cell(error(run.d, last), k == last);
            const std::string e_it = it100 ? cell(error(run.d, *it100), k == *it100) : "–";
            // cost per simulated second, so a smaller step counts its extra steps
            const double cpu_per_s = run.cpu_us / vs[k].dt * 1e-6;
            const double base = c.runs[0].cpu_us / vs[0].dt * 1e-6;
            std::printf(
                "| %s%d | %s | %+.4f | %+.4f | %s | %s | %.1f | %.3f | %.2f | %.3f | "
                "%.3f |\n",
                c.py ? "py" : "pp", c.n, vs[k].name, run.d.x, run.d.y, e_ref.c_str(), e_it.c_str(),
                run.cpu_us, cpu_per_s, cpu_per_s / base, run.max_separation * 1000,
                run.max_axis * 180 / 3.14159265358979);
        }
    }
    return 0;
}

// a fresh temporary folder, removed with its content
struct TempFolder {
    std::filesystem::path path;
    TempFolder() {
        std::string t = (std::filesystem::temp_directory_path() / "gaitlab_bench.XXXXXX").string();
        if (!mkdtemp(t.data())) throw std::runtime_error("cannot make a temporary folder");
        path = t;
    }
    ~TempFolder() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

// gaitlab with and without recording every series at every control tick, interleaved
int cmd_record(const Args& a) {
    const int reps = a.reps > 0 ? a.reps : (a.quick ? 3 : 5);
    const double seconds = a.seconds > 0 ? a.seconds : (a.quick ? 5 : 10);
    TempFolder tmp;
    std::printf(
        "\n### Recording every series at every control tick (thread CPU time per step, "
        "%g simulated s, median of %d interleaved runs)\n\n",
        seconds, reps);
    std::printf(
        "| scenario | series | gaitlab µs/step | recorded µs/step | ratio (CPU) | ratio "
        "range | data.csv MB per simulated s | same trajectory |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    std::vector<double> ratios;
    for (int ce : {30, 10}) {
        for (bool py : {false, true}) {
            Scenario sc;
            sc.modules = 16;
            sc.pitch_yaw = py;
            sc.control_every = ce;
            sc.seconds = seconds;
            std::vector<double> plain, recorded, r;
            bool same = true;
            const std::string dir = (tmp.path / "run").string();
            for (int rep = 0; rep < reps; ++rep) {
                const bool first_plain = rep % 2 == 0;
                Sample p, q;
                if (first_plain) p = run_once(Impl::gaitlab, sc, "");
                q = run_once(Impl::gaitlab, sc, "", dir);
                if (!first_plain) p = run_once(Impl::gaitlab, sc, "");
                plain.push_back(p.cpu_us);
                recorded.push_back(q.cpu_us);
                r.push_back(q.cpu_us / p.cpu_us);
                same = same && p.d.x == q.d.x && p.d.y == q.d.y && p.d.z == q.d.z;
                std::fprintf(stderr, "  %s repetition %d/%d done\n", sc.label().c_str(), rep + 1,
                             reps);
            }
            const double mb =
                static_cast<double>(std::filesystem::file_size(tmp.path / "run" / "data.csv")) /
                1e6 / seconds;
            const gaitlab::Simulation probe(make_world(sc), make_options(sc));
            const size_t series = gaitlab::SeriesSet(probe).size();
            std::printf("| %s | %zu | %.2f | %.2f | **%.3f** | %.3f–%.3f | %.2f | %s |\n",
                        sc.label().c_str(), series, median(plain), median(recorded), median(r),
                        min_of(r), max_of(r), mb, same ? "identical" : "DIFFERENT");
            ratios.push_back(median(r));
        }
    }
    double log_sum = 0;
    for (double x : ratios)
        log_sum += std::log(x);
    std::printf("\ngeometric mean of the CPU ratios: %.3f (target ≤ 1.05)\n",
                std::exp(log_sum / static_cast<double>(ratios.size())));
    return 0;
}

// resident memory of this process, kB: (VmRSS, VmHWM)
std::pair<long, long> memory_kb() {
    std::ifstream in("/proc/self/status");
    std::string line;
    long rss = 0, hwm = 0;
    while (std::getline(in, line)) {
        if (line.rfind("VmRSS:", 0) == 0) rss = std::atol(line.c_str() + 6);
        if (line.rfind("VmHWM:", 0) == 0) hwm = std::atol(line.c_str() + 6);
    }
    return {rss, hwm};
}

// a long recorded run: memory every 5 simulated minutes
int cmd_memory(const Args& a) {
    Scenario sc;
    sc.modules = a.one.modules;
    sc.control_every = a.ce > 0 ? a.ce : 30;
    TempFolder tmp;
    gaitlab::Simulation sim(make_world(sc), make_options(sc));
    gaitlab::RecordOptions o;
    o.dir = (tmp.path / "run").string();
    gaitlab::Recorder rec(sim, o);
    const long chunk = std::lround(300 / sc.dt);  // 5 simulated minutes
    const long total = std::lround(a.hours * 3600 / sc.dt);
    std::printf(
        "\n### Memory over a recorded run: %s, every series (%zu) at every control tick, "
        "%g simulated h\n\n",
        sc.label().c_str(), rec.series().size(), a.hours);
    std::printf("| simulated min | rows | data.csv MB | VmRSS MB | VmHWM MB | wall s |\n");
    std::printf("|---|---|---|---|---|---|\n");
    const Stopwatch w;
    long first_rss = 0, last_rss = 0;
    for (long done = 0; done < total; done += chunk) {
        sim.step(std::min(chunk, total - done));
        rec.flush();
        const auto [rss, hwm] = memory_kb();
        if (first_rss == 0) first_rss = rss;
        last_rss = rss;
        std::printf(
            "| %.0f | %ld | %.1f | %.1f | %.1f | %.0f |\n", sim.time() / 60, rec.rows(),
            static_cast<double>(std::filesystem::file_size(tmp.path / "run/data.csv")) / 1e6,
            static_cast<double>(rss) / 1024, static_cast<double>(hwm) / 1024, w.wall());
        std::fflush(stdout);
    }
    rec.close();
    std::printf(
        "\nresident memory after the first 5 simulated min: %.1f MB; at the end: %.1f MB "
        "(%+.1f MB)\n",
        static_cast<double>(first_rss) / 1024, static_cast<double>(last_rss) / 1024,
        static_cast<double>(last_rss - first_rss) / 1024);
    return 0;
}

int cmd_one(const Args& a) {
    const Sample s = run_once(a.impl, a.one, a.lua_file, a.record_dir);
    std::printf(
        "impl=%s scenario=\"%s\" ticks=%ld cpu_us_per_step=%.3f wall_us_per_step=%.3f "
        "dx=%.6f dy=%.6f dz=%.6f\n",
        to_string(a.impl), a.one.label().c_str(), a.one.ticks(), s.cpu_us, s.wall_us, s.d.x, s.d.y,
        s.d.z);
    return 0;
}

}  // namespace
}  // namespace gaitlab_bench

int main(int argc, char** argv) {
    using namespace gaitlab_bench;
    try {
        const Args a = parse(argc, argv);
        if (a.command == "overhead") return cmd_overhead(a);
        if (a.command == "lua") return cmd_lua(a);
        if (a.command == "accuracy") return cmd_accuracy(a);
        if (a.command == "one") return cmd_one(a);
        if (a.command == "record") return cmd_record(a);
        if (a.command == "memory") return cmd_memory(a);
        throw std::runtime_error("unknown command '" + a.command +
                                 "' (expected overhead, lua, accuracy, record, memory or one)");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gaitlab_bench: %s\n", e.what());
        return 2;
    }
}
