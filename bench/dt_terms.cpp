// dt_terms: which term of a step carries the time-step error of the pitch-yaw gaits
// (docs/performance.md, section 12). Steps the engine's physics through the raw Bullet loop
// (bench/raw_bullet_loop.cpp) at four settings, by default dt 1 ms / 20 iterations, dt 0.25 ms
// / 20, dt 1 ms / 80 and the reference dt 0.25 ms / 80, and prints the per-cycle displacement
// (mm along x / across y, 5 cycles of 2 s after 2 s) and the changes in % of its length
// (dt/4 and 4x it from the first setting, the first from the fourth), as
// bench/lua/convergence.lua does.
//
//   dt_terms [--per-step] [--method pgs|symmetric|nncg|block|block-nncg] [--check PCT] GAIT MODULES
//   FLOOR_FRICTION [PHASE0 [DT:IT DT:IT DT:IT DT:IT]]
//
// GAIT: pp, py-roll or py-wave (convergence.lua's gaits); --per-step: the friction rows chosen
// at the start of each step (FrictionModel::per_step in engine/src/bullet/coulomb_solver.h, the
// model before the friction disk) instead of the engine's friction disk; --method: the
// solver's iteration (SolverMethod there; pgs, the engine's, by default); --check PCT: exit 1
// when the first setting is more than PCT % off the fourth (a test of convergence).
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "raw_bullet_loop.h"
#include "scenario.h"

namespace gaitlab_bench {
namespace {

struct Result {
    double x = 0, y = 0;
};

Result run(const std::string& gait, int modules, double friction, double phase0, double dt,
           int iterations, bool per_step, const std::string& method) {
    Scenario sc;
    sc.friction_per_step = per_step;
    sc.solver_method = method;
    sc.modules = modules;
    sc.pitch_yaw = gait != "pp";
    sc.floor_friction = friction;
    sc.dt = dt;
    sc.control_every = static_cast<int>(std::lround(0.01 / dt));
    sc.solver_iterations = iterations;
    sc.phase0 = phase0;
    if (gait == "py-roll") {
        sc.phase = 0;
        sc.pitch_amplitude = 40;
        sc.yaw_amplitude = 40;
        sc.yaw_phase0 = -90;
    } else if (gait == "py-wave" || gait == "pp") {
        sc.phase = 120;
    } else {
        throw std::runtime_error("unknown gait '" + gait + "' (pp, py-roll or py-wave)");
    }
    RawSnake snake(sc);
    snake.step(std::lround(2.0 / dt));
    const Vec p = snake.displacement();
    const int cycles = 5;
    snake.step(std::lround(cycles * 2.0 / dt));
    const Vec q = snake.displacement();
    return {(q.x - p.x) * 1000 / cycles, (q.y - p.y) * 1000 / cycles};
}

double change(const Result& a, const Result& base) {
    return 100 * std::hypot(a.x - base.x, a.y - base.y) / std::hypot(base.x, base.y);
}

}  // namespace
}  // namespace gaitlab_bench

int main(int argc, char** argv) {
    using namespace gaitlab_bench;
    const char* usage =
        "usage: dt_terms [--per-step] [--method pgs|symmetric|nncg|block|block-nncg] [--check PCT] "
        "GAIT MODULES "
        "FLOOR_FRICTION [PHASE0 [DT:IT DT:IT DT:IT "
        "DT:IT]]";
    std::vector<std::string> args(argv + 1, argv + argc);
    bool per_step = false;
    std::string method = "pgs";
    double check = -1;
    try {
        while (!args.empty() && args[0].rfind("--", 0) == 0) {
            if (args[0] == "--per-step") {
                per_step = true;
                args.erase(args.begin());
            } else if (args[0] == "--check" && args.size() > 1) {
                check = std::stod(args[1]);
                args.erase(args.begin(), args.begin() + 2);
            } else if (args[0] == "--method" && args.size() > 1) {
                method = args[1];
                args.erase(args.begin(), args.begin() + 2);
            } else {
                throw std::runtime_error(usage);
            }
        }
        if (args.size() < 3) throw std::runtime_error(usage);
        const std::string gait = args[0];
        const int modules = std::stoi(args[1]);
        const double friction = std::stod(args[2]);
        const double phase0 = args.size() > 3 ? std::stod(args[3]) : 0;
        if (modules < 2 || !(friction > 0)) {
            throw std::runtime_error("MODULES must be at least 2 and FLOOR_FRICTION above 0");
        }
        double dts[4] = {0.001, 0.00025, 0.001, 0.00025};
        int its[4] = {20, 20, 80, 80};
        for (size_t k = 0; k < 4 && 4 + k < args.size(); ++k) {
            const std::string& a = args[4 + k];
            const size_t colon = a.find(':');
            if (colon == std::string::npos) {
                throw std::runtime_error("a setting is DT:IT, seconds and iterations (got '" + a +
                                         "')");
            }
            dts[k] = std::stod(a.substr(0, colon));
            its[k] = std::stoi(a.substr(colon + 1));
            if (!(dts[k] > 0) || its[k] < 1) {
                throw std::runtime_error("a setting needs DT > 0 and IT >= 1 (got '" + a + "')");
            }
        }
        Result r[4];
        std::string error;
        std::vector<std::thread> t;
        for (int k = 0; k < 4; k += 2) {
            t.emplace_back([&, k] {
                try {
                    for (int i = k; i < k + 2; ++i)
                        r[i] =
                            run(gait, modules, friction, phase0, dts[i], its[i], per_step, method);
                } catch (const std::exception& e) {
                    error = e.what();
                }
            });
        }
        for (auto& th : t)
            th.join();
        if (!error.empty()) throw std::runtime_error(error);
        std::printf(
            "| %s%s%s %d %.1f ph%g | %+.1f / %+.1f | %+.1f / %+.1f | %+.1f / %+.1f | "
            "%+.1f / %+.1f | %.1f | %.1f | %.1f |\n",
            gait.c_str(), per_step ? " per-step" : "",
            method == "pgs" ? "" : (" " + method).c_str(), modules, friction, phase0, r[0].x,
            r[0].y, r[1].x, r[1].y, r[2].x, r[2].y, r[3].x, r[3].y, change(r[1], r[0]),
            change(r[2], r[0]), change(r[0], r[3]));
        if (check >= 0 && !(change(r[0], r[3]) <= check)) {
            std::fprintf(stderr,
                         "dt_terms: the first setting is %.1f %% off the fourth (--check %g)\n",
                         change(r[0], r[3]), check);
            return 1;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dt_terms: %s\n", e.what());
        return 2;
    }
    return 0;
}
