// raw_bullet_loop: the benchmark snake stepped by plain Bullet (no gaitlab code).
//
//   raw_bullet_loop [--modules N] [--conn pp|py] [--ce C] [--iterations I] [--dt S] [--seconds S]
//                   [--method pgs|symmetric|nncg|block|block-nncg]
//
// Prints one line: the loop's time per step and the centre-of-mass displacement.
#include <chrono>
#include <cstdio>
#include <string>

#include "raw_bullet_loop.h"
#include "scenario.h"

int main(int argc, char** argv) {
    gaitlab_bench::Scenario sc;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i], v = argv[i + 1];
        if (k == "--modules") {
            sc.modules = std::stoi(v);
        } else if (k == "--conn") {
            sc.pitch_yaw = v == "py";
        } else if (k == "--ce") {
            sc.control_every = std::stoi(v);
        } else if (k == "--iterations") {
            sc.solver_iterations = std::stoi(v);
        } else if (k == "--dt") {
            sc.dt = std::stod(v);
        } else if (k == "--seconds") {
            sc.seconds = std::stod(v);
        } else if (k == "--method") {
            sc.solver_method = v;  // the solver's SolverMethod (RawSnake checks the name)
        } else {
            std::fprintf(stderr, "raw_bullet_loop: unknown option %s\n", k.c_str());
            return 2;
        }
    }
    if (sc.modules < 1 || sc.control_every < 1 || sc.solver_iterations < 1 || !(sc.dt > 0)) {
        std::fprintf(stderr, "raw_bullet_loop: invalid scenario\n");
        return 2;
    }
    if (sc.solver_method != "pgs" && sc.solver_method != "symmetric" &&
        sc.solver_method != "nncg" && sc.solver_method != "block" &&
        sc.solver_method != "block-nncg") {
        std::fprintf(stderr,
                     "raw_bullet_loop: --method is pgs, symmetric, nncg, block or block-nncg\n");
        return 2;
    }
    gaitlab_bench::RawSnake snake(sc);
    const auto t0 = std::chrono::steady_clock::now();
    snake.step(sc.ticks());
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const gaitlab_bench::Vec d = snake.displacement();
    std::printf("scenario=\"%s\" ticks=%ld us_per_step=%.3f dx=%.6f dy=%.6f contacts=%d\n",
                sc.label().c_str(), sc.ticks(), s * 1e6 / static_cast<double>(sc.ticks()), d.x, d.y,
                snake.contact_count());
    return 0;
}
