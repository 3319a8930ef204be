#include "gaitlab/world.h"

#include <fmt/format.h>

#include "check.h"
#include "gaitlab/error.h"

namespace gaitlab {

void validate(const WorldSpec& world) {
    detail::check_finite("gravity x", world.gravity.x);
    detail::check_finite("gravity y", world.gravity.y);
    detail::check_finite("gravity z", world.gravity.z);
    detail::check_range("floor friction", world.floor.friction, 0, 1);
    for (size_t i = 0; i < world.boxes.size(); ++i) {
        const BoxSpec& b = world.boxes[i];
        const std::string p = fmt::format("box {} ", i + 1);
        detail::check_positive(p + "size x", b.size.x, "m");
        detail::check_positive(p + "size y", b.size.y, "m");
        detail::check_positive(p + "size z", b.size.z, "m");
        detail::check_non_negative(p + "mass", b.mass, "kg");
        detail::check_range(p + "friction", b.friction, 0, 1);
        detail::check_finite(p + "position x", b.pose.position.x);
        detail::check_finite(p + "position y", b.pose.position.y);
        detail::check_finite(p + "position z", b.pose.position.z);
    }
    for (const PlacedRobot& r : world.robots)
        validate(r.robot);
}

}  // namespace gaitlab
