// Drives, the live form of an actuation (gaitlab/actuation.h): joint groups and the controller
// objects that drive them. Their checks name the controllers, so they belong to the stage that
// knows controllers; the value form (ActuationSpec, resolve_group) is in spec/actuation.cpp.
#include "gaitlab/actuation.h"

#include <algorithm>

#include <fmt/format.h>

#include "gaitlab/controller.h"
#include "gaitlab/error.h"

namespace gaitlab {

void check_new_group(const Actuation& drives, const Drive& drive, const std::string& robot) {
    std::vector<int> joints = drive.joints;
    std::sort(joints.begin(), joints.end());
    for (const Drive& d : drives) {
        std::vector<int> other = d.joints;
        std::sort(other.begin(), other.end());
        if (other != joints) continue;
        std::string list;
        for (int j : joints)
            list += fmt::format("{}{}", list.empty() ? "" : ", ", j + 1);
        const auto name = [](const Drive& x) {
            return x.controller ? x.controller->name() : std::string("?");
        };
        throw SpecError(fmt::format(
            "controller '{}' cannot drive joint{} {} of robot '{}': controller '{}' already "
            "drives exactly {} (one controller per group: their targets would add up; groups "
            "that only partly overlap do add)",
            name(drive), joints.size() == 1 ? "" : "s", list, robot, name(d),
            joints.size() == 1 ? "this joint" : "these joints"));
    }
}

}  // namespace gaitlab
