#include "scenario.h"

#include <cmath>
#include <cstdio>

namespace gaitlab_bench {

long Scenario::ticks() const {
    return std::lround(seconds / dt);
}

std::string Scenario::label() const {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s%d ce%d", pitch_yaw ? "py" : "pp", modules, control_every);
    std::string out = buf;
    if (solver_iterations != gaitlab::default_simulation_options().solver_iterations) {
        std::snprintf(buf, sizeof buf, " it%d", solver_iterations);
        out += buf;
    }
    if (dt != 0.001) {
        std::snprintf(buf, sizeof buf, " dt%gms", dt * 1000);
        out += buf;
    }
    return out;
}

}  // namespace gaitlab_bench
