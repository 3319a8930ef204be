// Actuation: joint groups, each driven by one controller.
#pragma once

#include <memory>
#include <vector>

namespace gaitlab {

class Controller;

/// A joint group and its controller. Groups of one robot may overlap; their targets add up.
struct Drive {
    std::vector<int> joints;                 ///< 0-based joint indices, at least one
    std::shared_ptr<Controller> controller;  ///< drives exactly this group
};

/// All drives of one robot.
using Actuation = std::vector<Drive>;

}  // namespace gaitlab
