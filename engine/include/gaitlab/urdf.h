// URDF interchange: any gaitlab robot exported as a URDF file (links with geometry and inertia,
// revolute joints with limits), and URDF serial chains of revolute joints imported as robots.
// See docs/formats.md#urdf.
#pragma once

#include <string>
#include <string_view>

#include "gaitlab/robot.h"

namespace gaitlab {

/// The robot as URDF text: one link per body, one revolute joint per joint. Every link frame
/// is parallel to the robot frame at rest; a joint's frame sits at its pivot. Throws SpecError
/// if the bodies and joints do not form a tree.
std::string format_urdf(const RobotSpec& robot);
/// Writes format_urdf(robot) atomically, creating missing folders above `path`; throws
/// SpecError or WriteError (an IoError naming `path`).
void write_urdf(const std::string& path, const RobotSpec& robot);

/// How an import takes the links' mass distribution.
struct UrdfImport {
    /// false: each link's <inertial> as the file gives it, its <inertia> and its centre of mass
    /// (the <inertial> origin), refused at their line where a gaitlab body cannot hold them;
    /// true: each link a uniform solid of its shape and <mass>, its <inertia> and the
    /// <inertial>'s origin not read (for files whose inertias are placeholders)
    bool inertia_from_shapes = false;
};

/// A robot from URDF text: a serial chain (each link has at most one child) of revolute
/// joints between links whose collision (or visual) geometry is a box or a cylinder. Servo speed,
/// torque and range come from each joint's <limit>, the gain is y1's; joints turning mostly about z
/// are yaw joints, about x roll joints, the others pitch. The robot is moved so its rearmost point
/// is at x = 0 and its lowest on the floor (z = 0), as gaitlab lays robots out. Throws FormatError
/// ("FILE:LINE: what was expected").
RobotSpec parse_urdf(std::string_view text, const std::string& file, const UrdfImport& how = {});
RobotSpec read_urdf(const std::string& path, const UrdfImport& how = {});

}  // namespace gaitlab
