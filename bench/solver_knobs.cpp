// solver_knobs: what Bullet solver settings that gaitlab does not expose would buy
// (docs/performance.md, section 13). It steps the engine's physics through the raw Bullet loop
// (bench/raw_bullet_loop.cpp: the engine's bodies, hinges, servo law and contact model, bit for
// bit) with the solver settings changed, and measures each variant as bench/anchors.sh measures
// the engines: the per-cycle speed against a converged reference, and the CPU time per step.
//
//   solver_knobs [--modules N] [--reps R] [--jobs J] [--quick] [--ideas] [--only TEXT]
//
// --ideas: instead of the solver settings, the ideas that need code (RawOptions): Bullet's
// convex-plane path instead of the engine's box-plane collider (engine/src/bullet/box_plane.h),
// fewer points per box face, and other
// iteration counts for the joints than for the contacts, each at several iteration counts and
// at dt 1 and 0.5 ms, so that each can be compared at equal accuracy. --only TEXT keeps the
// variants whose name contains TEXT (besides the reference and the engine's default).
//
// Accuracy: 22 simulated s, the centre of mass sampled every 2 s (a gait cycle), speed = mean
// |displacement| per cycle over cycles 2-11, pitch-yaw averaged over 5 start phases (0, 72,
// 144, 216, 288 deg). Reference: dt 0.25 ms, 80 iterations, the engine's settings. Timing: R
// rounds of every variant for 10 simulated s, the order reversed every other round; median
// thread CPU time per step. The control period stays 10 ms at every dt.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "raw_bullet_loop.h"
#include "scenario.h"

namespace gaitlab_bench {
namespace {

const char* const kUsage =
    "solver_knobs [--modules N] [--reps R] [--jobs J] [--quick] [--ideas] [--only TEXT]";

struct Variant {
    std::string name;
    double dt = 0.001;
    int iterations = 20;
    std::function<void(btContactSolverInfo&)> knob;  // empty: the engine's settings
    RawOptions options = {};                         // the engine's contacts and joints
};

std::vector<Variant> variants() {
    auto warm = [](btScalar f) {
        return [f](btContactSolverInfo& i) { i.m_warmstartingFactor = f; };
    };
    auto no_split = [](btContactSolverInfo& i) { i.m_splitImpulse = 0; };
    auto residual = [](btScalar r) {
        return [r](btContactSolverInfo& i) { i.m_leastSquaresResidualThreshold = r; };
    };
    auto mode_off = [](int flag) {
        return [flag](btContactSolverInfo& i) { i.m_solverMode &= ~flag; };
    };
    auto mode_on = [](int flag) {
        return [flag](btContactSolverInfo& i) { i.m_solverMode |= flag; };
    };
    return {
        {"reference: dt 0.25 ms, 80 it", 0.00025, 80, {}},
        {"engine default: 20 it", 0.001, 20, {}},
        {"14 it", 0.001, 14, {}},
        {"10 it", 0.001, 10, {}},
        {"7 it", 0.001, 7, {}},
        {"dt 2 ms, 10 it", 0.002, 10, {}},
        {"dt 2 ms, 20 it", 0.002, 20, {}},
        {"warm-start factor 1 (0.85), 20 it", 0.001, 20, warm(1)},
        {"warm-start factor 1 (0.85), 10 it", 0.001, 10, warm(1)},
        {"warm-start factor 1 (0.85), 7 it", 0.001, 7, warm(1)},
        {"no warm starting, 20 it", 0.001, 20, mode_off(SOLVER_USE_WARMSTARTING)},
        {"no split impulse, 20 it", 0.001, 20, no_split},
        {"no split impulse, 10 it", 0.001, 10, no_split},
        {"residual threshold 1e-10, 20 it", 0.001, 20, residual(btScalar(1e-10))},
        {"residual threshold 1e-12, 20 it", 0.001, 20, residual(btScalar(1e-12))},
        {"interleave contact and friction rows, 20 it", 0.001, 20,
         mode_on(SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS)},
        {"interleave contact and friction rows, 10 it", 0.001, 10,
         mode_on(SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS)},
        {"no SIMD, 20 it", 0.001, 20, mode_off(SOLVER_SIMD)},
    };
}

// the ideas of issue 14 that need more than a solver setting: contact points from Bullet's
// convex-plane path (what the engine's box-plane collider replaced) or 4 only for a flat face,
// and the
// joints' rows solved in another number of iterations than the contacts'
std::vector<Variant> idea_variants() {
    using C = RawOptions::Contacts;
    std::vector<Variant> v;
    for (double dt : {0.001, 0.0005}) {
        const bool one = dt == 0.001;
        const std::string at = one ? "" : "dt 0.5 ms, ";
        const std::vector<int> counts =
            one ? std::vector<int>{20, 14, 10, 7, 5} : std::vector<int>{10, 7, 5};
        for (int it : counts) {
            const std::string its = std::to_string(it) + " it";
            if (!one || it != 20) v.push_back({at + its, dt, it, {}, {}});
            v.push_back({"Bullet's multipoint path (the engine's before), " + at + its,
                         dt,
                         it,
                         {},
                         {C::bullet_multipoint, 0}});
            v.push_back({"box-plane, 4 points if flat else 2, " + at + its,
                         dt,
                         it,
                         {},
                         {C::box_plane_fewer, 0}});
        }
        const std::vector<std::pair<int, int>> split =
            one ? std::vector<std::pair<int, int>>{{5, 10},  {7, 20}, {10, 5},
                                                   {10, 20}, {20, 7}, {20, 10}}
                : std::vector<std::pair<int, int>>{{5, 10}, {7, 14}};
        for (auto [contacts, joints] : split) {
            v.push_back({at + "contacts " + std::to_string(contacts) + " it, joints " +
                             std::to_string(joints) + " it",
                         dt,
                         contacts,
                         {},
                         {C::engine, joints}});
        }
    }
    return v;
}

Scenario scenario(const Variant& v, int modules, bool py, double phase0, double seconds) {
    Scenario s;
    s.modules = modules;
    s.pitch_yaw = py;
    s.dt = v.dt;
    s.control_every = static_cast<int>(std::lround(0.01 / v.dt));
    s.solver_iterations = v.iterations;
    s.phase0 = phase0;
    s.seconds = seconds;
    return s;
}

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// mean |centre-of-mass displacement| per 2 s cycle over cycles 2..11, mm
double cycle_speed(const Variant& v, int modules, bool py, double phase0) {
    const Scenario sc = scenario(v, modules, py, phase0, 22);
    RawSnake snake(sc, v.options);
    if (v.knob) v.knob(snake.solver_info());
    const long cycle = std::lround(2.0 / v.dt);
    snake.step(cycle);
    Vec p = snake.displacement();
    double sum = 0;
    for (int k = 0; k < 10; ++k) {
        snake.step(cycle);
        const Vec q = snake.displacement();
        sum += std::hypot(q.x - p.x, q.y - p.y);
        p = q;
    }
    if (!std::isfinite(sum)) throw std::runtime_error(v.name + ": the robot diverged");
    return sum / 10 * 1000;
}

double cpu_us_per_step(const Variant& v, int modules, bool py, double seconds) {
    const Scenario sc = scenario(v, modules, py, 0, seconds);
    RawSnake snake(sc, v.options);
    if (v.knob) v.knob(snake.solver_info());
    const double c0 = thread_cpu_seconds();
    snake.step(sc.ticks());
    return (thread_cpu_seconds() - c0) * 1e6 / static_cast<double>(sc.ticks());
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t k = v.size() / 2;
    return v.size() % 2 ? v[k] : (v[k - 1] + v[k]) / 2;
}

int run(int argc, char** argv) {
    int modules = 8, reps = 5, jobs = 2;
    bool quick = false, ideas = false;
    std::string only;
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        auto value = [&]() -> int {
            if (i + 1 >= argc) throw std::runtime_error(k + " needs a value");
            const std::string v = argv[++i];
            size_t used = 0;
            int x = 0;
            try {
                x = std::stoi(v, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != v.size() || x < 1) {
                throw std::runtime_error(k + " takes a positive integer (got '" + v + "')");
            }
            return x;
        };
        if (k == "--modules") {
            modules = value();
        } else if (k == "--reps") {
            reps = value();
        } else if (k == "--jobs") {
            jobs = value();
        } else if (k == "--quick") {
            quick = true;
        } else if (k == "--ideas") {
            ideas = true;
        } else if (k == "--only") {
            if (i + 1 >= argc) throw std::runtime_error("--only needs a value");
            only = argv[++i];
        } else {
            throw std::runtime_error("unknown option '" + k + "' (" + kUsage + ")");
        }
    }
    // the reference and the engine's default first, then the variants asked for
    std::vector<Variant> vs;
    {
        const std::vector<Variant> all = ideas ? idea_variants() : variants();
        vs = {{"reference: dt 0.25 ms, 80 it", 0.00025, 80, {}, {}},
              {"engine default: 20 it", 0.001, 20, {}, {}}};
        for (const Variant& v : all) {
            if (v.name == vs[0].name || v.name == vs[1].name) continue;
            if (only.empty() || v.name.find(only) != std::string::npos) vs.push_back(v);
        }
    }
    const std::vector<double> phases_py =
        quick ? std::vector<double>{0, 144} : std::vector<double>{0, 72, 144, 216, 288};
    if (quick) reps = std::min(reps, 3);

    // accuracy: every (connection, variant, phase) once, `jobs` at a time (deterministic runs)
    struct Job {
        bool py;
        size_t variant;
        size_t phase;
        double speed = 0;
    };
    std::vector<Job> work;
    for (bool py : {false, true}) {
        const size_t np = py ? phases_py.size() : 1;
        for (size_t v = 0; v < vs.size(); ++v)
            for (size_t p = 0; p < np; ++p)
                work.push_back({py, v, p});
    }
    std::atomic<size_t> next{0};
    std::vector<std::string> errors(static_cast<size_t>(jobs));
    auto worker = [&](size_t id) {
        for (size_t k; (k = next++) < work.size();) {
            Job& j = work[k];
            try {
                j.speed = cycle_speed(vs[j.variant], modules, j.py, j.py ? phases_py[j.phase] : 0);
            } catch (const std::exception& e) {
                j.speed = NAN;
                errors[id] = e.what();
            }
        }
    };
    std::fprintf(stderr, "solver_knobs: %zu accuracy runs, %d at a time\n", work.size(), jobs);
    std::vector<std::thread> threads;
    for (size_t t = 0; t < static_cast<size_t>(jobs); ++t)
        threads.emplace_back(worker, t);
    for (auto& t : threads)
        t.join();

    // timing: interleaved rounds, one run at a time
    std::vector<std::vector<double>> cpu(2 * vs.size());
    const double seconds = quick ? 4 : 10;
    for (int r = 0; r < reps; ++r) {
        for (size_t k = 0; k < 2 * vs.size(); ++k) {
            const size_t idx = r % 2 ? 2 * vs.size() - 1 - k : k;
            const size_t v = idx % vs.size();
            if (v == 0) continue;  // the reference's cost is not compared
            cpu[idx].push_back(cpu_us_per_step(vs[v], modules, idx >= vs.size(), seconds));
        }
        std::fprintf(stderr, "  timing round %d/%d done\n", r + 1, reps);
    }

    std::printf(
        "| conn | variant | speed (mm/cycle) | error vs reference | worst start phase | "
        "CPU µs/step (median) | range | vs engine default |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (bool py : {false, true}) {
        const size_t np = py ? phases_py.size() : 1;
        auto speeds = [&](size_t v) {
            std::vector<double> s;
            for (const Job& j : work)
                if (j.py == py && j.variant == v) s.push_back(j.speed);
            return s;
        };
        auto mean = [](const std::vector<double>& s) {
            double t = 0;
            for (double x : s)
                t += x;
            return t / static_cast<double>(s.size());
        };
        const std::vector<double> ref = speeds(0);
        const double ref_mean = mean(ref);
        const double base = median(cpu[(py ? vs.size() : 0) + 1]);
        for (size_t v = 0; v < vs.size(); ++v) {
            const std::vector<double> s = speeds(v);
            const double m = mean(s);
            double worst = 0;
            for (size_t p = 0; p < np; ++p)
                worst = std::max(worst, std::abs(s[p] - ref[p]) / ref[p] * 100);
            const double err = (m - ref_mean) / ref_mean * 100;
            char errtext[48], worsttext[32], cputext[96];
            if (v == 0) {
                std::snprintf(errtext, sizeof errtext, "(reference)");
                std::snprintf(worsttext, sizeof worsttext, "—");
                std::snprintf(cputext, sizeof cputext, "— | — | —");
            } else {
                std::snprintf(errtext, sizeof errtext,
                              std::abs(err) > 2 ? "**%+.2f %%**" : "%+.2f %%", err);
                if (py) {
                    std::snprintf(worsttext, sizeof worsttext, "%.2f %%", worst);
                } else {
                    std::snprintf(worsttext, sizeof worsttext, "—");
                }
                const std::vector<double>& c = cpu[(py ? vs.size() : 0) + v];
                const double med = median(c);
                const double per_ms = med / (vs[v].dt * 1000);
                const double base_per_ms = base;  // the default runs at dt 1 ms
                std::snprintf(cputext, sizeof cputext, "%.2f | %.1f–%.1f | ×%.2f", med,
                              *std::min_element(c.begin(), c.end()),
                              *std::max_element(c.begin(), c.end()), per_ms / base_per_ms);
            }
            std::printf("| %s%d | %s | %.1f | %s | %s | %s |\n", py ? "py" : "pp", modules,
                        vs[v].name.c_str(), m, errtext, worsttext, cputext);
        }
    }
    std::printf("\n(\"vs engine default\": CPU time per simulated second over the default's.)\n");
    for (const std::string& e : errors)
        if (!e.empty()) {
            std::fprintf(stderr, "solver_knobs: %s\n", e.c_str());
            return 1;
        }
    return 0;
}

}  // namespace
}  // namespace gaitlab_bench

int main(int argc, char** argv) {
    try {
        return gaitlab_bench::run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "solver_knobs: %s\n", e.what());
        return 2;
    }
}
