// Robot specs: plain values describing bodies and joints, and the chain builder.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gaitlab/module.h"
#include "gaitlab/sensor.h"
#include "gaitlab/types.h"

namespace gaitlab {

/// Limits of robot specs (docs/formats.md).
inline constexpr int kMaxModules = 1000;       ///< modules of one chain
inline constexpr int kMaxRobotBodies = 10000;  ///< bodies of one robot (joints: as many)
inline constexpr double kMaxBodyExtent = 100;  ///< m, each size of a body
inline constexpr double kMaxBodyMass = 1e6;    ///< kg
/// m, each size of a body: a chain of modules 0.2 mm long (its end bodies 0.1 mm) moves as one
/// 100 times larger at dt 0.1 ms, and 10 % less at the default 1 ms (docs/formats.md, Limits)
inline constexpr double kMinBodyExtent = 1e-4;
/// kg: a cube of water kMinBodyExtent wide; at the default dt and solver 5 cm modules of
/// 1e-18 kg still move as heavier ones, and of 1e-20 kg diverge (single precision's end)
inline constexpr double kMinBodyMass = 1e-9;
/// a body's longest side over its second longest (a cylinder's length over its diameter): the
/// solver's rows of a slender body hold its inertia about its long axis, about (longest /
/// second)^2 times smaller than about the others, in single precision. Driven chains of 8 such
/// bodies stay finite at 300 at every mass and torque and diverge from 700 (docs/formats.md,
/// Limits)
inline constexpr double kMaxBodySlenderness = 300;
/// a body's largest principal moment of inertia over its smallest: that of a body 300 times
/// longer than wide (kMaxBodySlenderness squared), whose long axis the solver's single-precision
/// rows hold no better
inline constexpr double kMaxInertiaRatio = kMaxBodySlenderness * kMaxBodySlenderness;
/// each principal moment of a given inertia over the uniform solid's about the same axis, at
/// least: a tenth of the radius of gyration. Chains of 8 bodies with moments a hundredth of their
/// solid's stay finite at every mass and size (docs/formats.md, Limits)
inline constexpr double kMinInertiaFraction = 0.01;
/// m, the radius of every cylinder (bodies, modules, world objects): Bullet rounds a shape by
/// its 1 mm collision margin, and a thinner cylinder sinks into the floor
inline constexpr double kMinCylinderRadius = 1e-3;

/// How consecutive modules of a chain are joined.
enum class Connection { pitch_pitch, pitch_yaw, yaw_yaw };

/// What a joint does when the robot lies straight on the floor.
enum class JointRole {
    pitch,  ///< bends the chain up and down
    yaw,    ///< bends the chain left and right
    roll,   ///< twists the chain about its own axis (modules whose axis is "twist")
};

/// "pitch-pitch", "pitch-yaw" or "yaw-yaw".
const char* to_string(Connection c);
/// "pitch", "yaw" or "roll".
const char* to_string(JointRole r);
/// Parses a connection name; throws SpecError naming the valid ones.
Connection parse_connection(std::string_view name);

/// One rigid body of a robot: a box, or a cylinder along the body's x axis.
struct BodySpec {
    std::string name;
    Shape shape = Shape::box;
    Vec3 size;    ///< box: full extents along x, y, z; cylinder: length, diameter, diameter; m
    double mass;  ///< kg, in [kMinBodyMass, kMaxBodyMass]
    Pose pose;    ///< at rest, in the robot frame
    double friction = 1.0;  ///< in [0, 1]
    /// kg·m², the principal moments of inertia about axes through the centre of mass parallel to
    /// the body's x, y and z axes (a cylinder's x is its axis); none: the solid's, from size and
    /// mass (about the centre of mass too, wherever it is). Each positive, at least
    /// kMinInertiaFraction of the solid's, at most the mass times the square of half the body's
    /// diagonal, at most kMaxInertiaRatio times another and at most the sum of the other two
    std::optional<Vec3> inertia;
    /// m, the centre of mass in the body's own frame, from its shape's centre; none: at the
    /// shape's centre (a body given {0, 0, 0} is one without it, to the bit).
    /// Finite and inside the shape: a box's within its half sizes, a cylinder's within its half
    /// length and its radius. Poses (`pose`, the simulation's body states) stay the shape's
    std::optional<Vec3> center_of_mass;
};

/// A revolute joint between two bodies, driven by a servo.
struct JointSpec {
    std::string name;
    JointRole role = JointRole::pitch;
    int parent = 0;  ///< body on the tail side (index into RobotSpec::bodies)
    int child = 1;   ///< body on the head side
    Vec3 pivot;      ///< at rest, in the robot frame, m
    Vec3 axis;       ///< unit vector in the robot frame; positive angles turn the child about it
    double min_angle = 0;  ///< rad
    double max_angle = 0;  ///< rad
    ServoDef servo;
};

/// A straight chain of identical modules. Modules whose axis is "twist" make roll joints
/// whatever the connection; a pitch-yaw chain of box modules needs a square cross-section.
struct ChainSpec {
    std::string name = "robot";
    int modules = 1;  ///< >= 1
    Connection connection = Connection::pitch_pitch;
    ModuleDef module = default_module_def();
};

/// A robot: bodies, the joints between them, and options. The robot frame has its tail at the
/// origin, the chain along +x and the floor at z = 0.
struct RobotSpec {
    std::string name = "robot";
    std::vector<BodySpec> bodies;
    std::vector<JointSpec> joints;
    bool self_collision = false;  ///< collide non-adjacent bodies of the robot with each other
    /// The chain make_chain built this robot from, if it did: robot files then store the chain
    /// rather than every body and joint (when the bodies and joints are still the chain's).
    std::optional<ChainSpec> chain;
    /// sensors on its modules and joints, in the order simulations number them (sensor.h)
    std::vector<SensorSpec> sensors;
};

/// Builds a chain of N modules: N joints and N + 1 bodies (tail half, N - 1 segments, head half),
/// lying along +x with its tail at the origin. Throws SpecError on invalid input.
RobotSpec make_chain(const ChainSpec& spec);

/// Checks a robot spec (names, indices, masses, sizes, ranges, friction, sensors, the limits
/// above); throws SpecError.
void validate(const RobotSpec& robot);
/// Checks a name that becomes part of series names, file names and JSON strings (a robot's, a
/// placement's, a simulation's): valid UTF-8 without control characters (a zero byte too), at
/// most kMaxNameBytes; `what` starts the message ("robot name must be ..."); throws SpecError.
void validate_name(const std::string& what, std::string_view name);
/// Checks one body of the robot called `robot_name` (its name, mass, size, friction), as
/// validate does; throws SpecError ("robot 'snake' body 'tail' mass must be positive ...").
void validate_body(const std::string& robot_name, const BodySpec& body);
/// Checks one joint against the bodies of `robot` (its name, the bodies it joins, axis, range,
/// servo), as validate does; throws SpecError.
void validate_joint(const RobotSpec& robot, const JointSpec& joint);

/// Joint indices (0-based, from the tail) selected by role: "pitch", "yaw", "roll" or "all". Throws
/// SpecError for an unknown role or an empty selection.
std::vector<int> select_joints(const RobotSpec& robot, std::string_view role);

/// kg·m², the principal moments of inertia of `body` about its x, y and z axes: its given
/// inertia, or its solid's (a uniform box or cylinder of its size and mass, as the simulation
/// computes it, there in single precision).
Vec3 body_inertia(const BodySpec& body);

/// Total mass, kg.
double total_mass(const RobotSpec& robot);

/// Field-by-field equality (exact), as robot files must give back what was saved.
bool operator==(const BodySpec& a, const BodySpec& b);
bool operator==(const JointSpec& a, const JointSpec& b);
bool operator==(const ChainSpec& a, const ChainSpec& b);
bool operator==(const SensorSpec& a, const SensorSpec& b);
bool operator==(const RobotSpec& a, const RobotSpec& b);
inline bool operator!=(const RobotSpec& a, const RobotSpec& b) {
    return !(a == b);
}

}  // namespace gaitlab
