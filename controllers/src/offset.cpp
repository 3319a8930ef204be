#include "gaitlab/controllers/offset.h"

#include "gaitlab/types.h"

namespace gaitlab::controllers {

Offset::Offset() : Controller(ControllerDef{"offset", {{"angle", 0, -90, 90, "deg"}}, {}}) {}

void Offset::step(ControlIO& io) {
    const double target = deg_to_rad(param(angle));
    for (int m = 0; m < io.joints(); ++m)
        io.set_target(m, target);
}

std::unique_ptr<Controller> Offset::clone() const {
    return std::unique_ptr<Controller>(new Offset(*this));
}

}  // namespace gaitlab::controllers
