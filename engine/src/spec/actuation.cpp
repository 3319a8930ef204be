#include "gaitlab/actuation.h"

#include <algorithm>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/robot.h"

namespace gaitlab {

const char* to_string(ControllerRef::Kind kind) {
    switch (kind) {
        case ControllerRef::Kind::builtin:
            return "builtin";
        case ControllerRef::Kind::file:
            return "file";
        case ControllerRef::Kind::template_:
            return "template";
    }
    return "builtin";
}

std::vector<int> resolve_group(const GroupSpec& group, const RobotSpec& robot) {
    if (!group.role.empty()) {
        if (!group.joints.empty())
            throw SpecError("a group is a role or a list of joints, not both");
        return select_joints(robot, group.role);
    }
    if (group.joints.empty()) throw SpecError("a joint group needs at least one joint");
    const int n = static_cast<int>(robot.joints.size());
    std::vector<int> seen;
    for (int j : group.joints) {
        if (j < 0 || j >= n) {
            throw SpecError(fmt::format("robot '{}' has no joint {} (it has joints 1 to {})",
                                        robot.name, j + 1, n));
        }
        if (std::find(seen.begin(), seen.end(), j) != seen.end()) {
            throw SpecError(fmt::format("joint {} is listed twice", j + 1));
        }
        seen.push_back(j);
    }
    return group.joints;
}

}  // namespace gaitlab
