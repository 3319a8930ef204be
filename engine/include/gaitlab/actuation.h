// Actuation: joint groups, each driven by one controller. `Actuation` is the live form (the
// controller objects of a robot); `ActuationSpec` is the value form an actuation file stores
// (which controller, with which parameter values) and from which the live form is built.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace gaitlab {

class Controller;
struct RobotSpec;

/// A joint group and its controller. Groups of one robot may overlap partly, and then their
/// targets add up (an offset on every joint plus a sine on the pitch joints); two groups of
/// exactly the same joints are an error (check_new_group).
struct Drive {
    std::vector<int> joints;                 ///< 0-based joint indices, at least one
    std::shared_ptr<Controller> controller;  ///< drives exactly this group
};

/// All drives of one robot.
using Actuation = std::vector<Drive>;

/// Which controller drives a group, as a file names it.
struct ControllerRef {
    enum class Kind {
        builtin,   ///< a built-in controller: `name` is e.g. "sine"
        file,      ///< a Lua controller file: `name` is its path
        template_  ///< an embedded controller template: `name` is e.g. "cpg_chain"
    };
    Kind kind = Kind::builtin;
    std::string name;
    /// Parameter values by name, in the parameter's unit; the others keep their defaults.
    std::vector<std::pair<std::string, double>> params;
    std::string source;  ///< the file it was read from ("" if built in code), for messages
    int line = 0;        ///< its line in that file

    bool operator==(const ControllerRef& o) const {
        return kind == o.kind && name == o.name && params == o.params;
    }
};

/// "builtin", "file" or "template".
const char* to_string(ControllerRef::Kind kind);

/// A joint group and the controller that drives it. The group is a role ("pitch", "yaw",
/// "all") or a list of joints; exactly one of the two is given.
struct GroupSpec {
    std::string role;
    std::vector<int> joints;  ///< 0-based
    ControllerRef controller;

    bool operator==(const GroupSpec& o) const {
        return role == o.role && joints == o.joints && controller == o.controller;
    }
};

/// The groups of one robot and their controllers.
struct ActuationSpec {
    std::vector<GroupSpec> groups;

    bool operator==(const ActuationSpec& o) const { return groups == o.groups; }
};

/// Throws SpecError if a drive of `drives` has exactly the joints of `drive` (in any order):
/// "controller 'offset' cannot drive joints 1, 3 of robot 'snake': controller 'sine' already
/// drives exactly these joints (...)". Groups that only partly overlap pass. `robot` is the
/// robot's name.
void check_new_group(const Actuation& drives, const Drive& drive, const std::string& robot);

/// The 0-based joints of `robot` that `group` selects; throws SpecError (unknown role, a
/// joint the robot does not have, a joint named twice, an empty group).
std::vector<int> resolve_group(const GroupSpec& group, const RobotSpec& robot);

}  // namespace gaitlab
