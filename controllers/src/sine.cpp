#include "gaitlab/controllers/sine.h"

#include <cmath>

#include "gaitlab/types.h"

namespace gaitlab::controllers {

Sine::Sine()
    : Controller(ControllerDef{"sine",
                               {{"amplitude", 40, 0, 90, "deg"},
                                {"frequency", 0.5, 0, 5, "Hz"},
                                {"phase", 120, -180, 180, "deg"},
                                {"phase0", 0, -180, 180, "deg"},
                                {"offset", 0, -90, 90, "deg"}},
                               {"time", "angle"}}) {}

void Sine::step(ControlIO& io) {
    const double a = param(amplitude), f = param(frequency), dphi = deg_to_rad(param(phase));
    const double phi0 = deg_to_rad(param(phase0)), o = param(offset);
    std::vector<double>& t = value(time);
    std::vector<double>& out = value(angle);
    // each joint keeps its own clock, advanced before use; the expression keeps the operation
    // order of the Lua version in examples/controllers/my_sine.lua so both agree bit for bit
    for (int m = 0; m < io.joints(); ++m) {
        t[m] = t[m] + io.dt();
        out[m] = a * std::sin(2 * kPi * f * t[m] + static_cast<double>(m) * dphi + phi0) + o;
        io.set_target(m, deg_to_rad(out[m]));
    }
}

std::unique_ptr<Controller> Sine::clone() const {
    return std::unique_ptr<Controller>(new Sine(*this));
}

}  // namespace gaitlab::controllers
