// World specs: gravity, floor, the objects of the world library, and the robots placed in them.
// Every object is a plain value holding its parameters (a staircase is its step count and sizes,
// a rubble field its area, count, size ranges and seed); compiling a simulation expands them
// into rigid bodies (see geometry.h). Angles are radians; messages show them in degrees.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gaitlab/actuation.h"
#include "gaitlab/robot.h"
#include "gaitlab/types.h"

namespace gaitlab {

/// Limits of world specs (docs/formats.md lists them): beyond them Bullet's single-precision
/// geometry means nothing any more, or the world would not fit in memory.
inline constexpr double kMaxGravity = 1000;        ///< m/s², each component, in [-max, max]
inline constexpr double kMaxCoordinate = 10000;    ///< m: positions of objects and robots
inline constexpr double kMaxExtent = 10000;        ///< m: sizes, lengths, radii of objects
inline constexpr double kMaxObjectMass = 1e6;      ///< kg
inline constexpr double kMaxTerrainHeight = 1000;  ///< m: heightfield heights, in [-max, max]
inline constexpr int kMaxStairsSteps = 1000;
inline constexpr int kMaxPipeSides = 256;
inline constexpr int kMaxRubbleCount = 100000;        ///< stones of one rubble field
inline constexpr int kMaxHeightfieldSide = 4096;      ///< samples along each side of one grid
inline constexpr long long kMaxWorldSolids = 250000;  ///< bodies all objects expand into
/// samples of all heightfields together (one 4096 × 4096 grid)
inline constexpr long long kMaxHeightSamples = 4096LL * 4096;
inline constexpr int kMaxRobots = 1000;  ///< robots in one world
/// m: sizes and lengths of objects, as a robot body's (kMinBodyExtent); cylinders' radii are at
/// least kMinCylinderRadius
inline constexpr double kMinExtent = 1e-4;
/// kg, of an object that moves (0 makes it static), as a robot body's (kMinBodyMass)
inline constexpr double kMinObjectMass = 1e-9;
/// N/m and N·s/m: a compliant floor's stiffness and damping at most this (Bullet's contact rows
/// hold dt · stiffness + damping in single precision)
inline constexpr double kMaxFloorStiffness = 1e12;
inline constexpr double kMaxFloorDamping = 1e12;

/// N/m and N·s/m: the floor's stiffness and damping per contact point when a script gives
/// neither. Soft enough that dt 1 ms resolves the contact of a module's lightest body (a 25 g
/// half-module: on a floor of 1e5 N/m its contact settled in about 0.5 ms, and gaits whose speed
/// depends on the floor then moved 3-8 % differently at dt / 4; here it relaxes in c / k =
/// 20 ms), stiff enough that robots sink by tens of micrometres (a 0.05 kg module resting on its
/// 8 corners: 20 µm; a 1 kg body on 4: 0.8 mm), and it makes each contact's forces unique where a
/// rigid floor's are not (docs/performance.md, section 12, "A floor dt 1 ms resolves")
inline constexpr double kDefaultFloorStiffness = 3e3;
inline constexpr double kDefaultFloorDamping = 60;

/// An infinite static plane at z = 0. Compliant by default: every contact point on it is a
/// spring of `stiffness` and a damper of `damping` along the normal, implicit in the step, so a
/// body of weight W resting on n points sinks by W / (n · stiffness). `rigid` makes it a hard
/// constraint instead (the solver's projection, with no stiffness or damping).
struct FloorSpec {
    bool enabled = true;    ///< false: no floor
    double friction = 1.0;  ///< in [0, 1]
    bool rigid = false;     ///< true: a rigid floor (then no stiffness and no damping)
    /// N/m per contact point, in (0, 1e12]; absent: kDefaultFloorStiffness
    std::optional<double> stiffness;
    /// N·s/m per contact point, in [0, 1e12]; absent: kDefaultFloorDamping
    std::optional<double> damping;
};

/// A box obstacle. mass = 0 makes it static; a box that moves is at most kMaxBodySlenderness
/// times as long as its second longest side, as a robot body.
struct BoxSpec {
    Vec3 size{0.1, 0.1, 0.1};  ///< full extents, m, > 0
    Pose pose;                 ///< centre and orientation, world frame
    double mass = 0;           ///< kg: 0 (static) or in [kMinObjectMass, kMaxObjectMass]
    double friction = 1.0;     ///< in [0, 1]
};

/// A static wall: a thin upright box standing on its base.
struct WallSpec {
    double length = 1.0;      ///< along its local x, m, > 0
    double height = 0.1;      ///< m, > 0
    double thickness = 0.02;  ///< m, > 0
    Vec3 position;            ///< centre of its base, world frame, m
    double yaw = 0;           ///< rad about +z; 0: the wall runs along x
    double friction = 1.0;    ///< in [0, 1]
};

/// A static ramp: a wedge whose top face rises from its lower edge towards its local +x, with a
/// vertical back face. Its top edge is length · tan(slope) above its lower edge.
struct RampSpec {
    double slope = 0.17453292519943295;  ///< rad, in (0, 90°); default 10°
    double length = 0.5;                 ///< horizontal run of the slope, m, > 0
    double width = 0.5;                  ///< across, along its local y, m, > 0
    Vec3 position;                       ///< centre of the lower edge, world frame, m
    double yaw = 0;                      ///< rad about +z; 0: rises towards +x
    double friction = 1.0;               ///< in [0, 1]
};

/// A static staircase rising towards its local +x: step k (1-based) is a block from the ground
/// to k · step_height, step_depth deep; the top step is `landing` deeper.
struct StairsSpec {
    int steps = 3;              ///< number of steps, in [1, 1000]
    double step_height = 0.02;  ///< rise of each step, m, > 0
    double step_depth = 0.2;    ///< tread of each step, m, > 0
    double width = 0.5;         ///< across, along its local y, m, > 0
    double landing = 0;         ///< extra depth of the top step, m, >= 0
    Vec3 position;              ///< centre of the first step's front edge at its foot, m
    double yaw = 0;             ///< rad about +z; 0: rises towards +x
    double friction = 1.0;      ///< in [0, 1]
};

/// A cylinder, upright or lying. mass = 0 makes it static; a cylinder that moves is at most
/// kMaxBodySlenderness times as long as its diameter, as a robot body.
struct CylinderSpec {
    double radius = 0.05;   ///< m, > 0
    double length = 0.1;    ///< along its axis, m, > 0
    bool lying = false;     ///< false: axis along z; true: axis along its local x
    Vec3 position;          ///< centre, world frame, m
    double yaw = 0;         ///< rad about +z
    double mass = 0;        ///< kg: 0 (static) or in [kMinObjectMass, kMaxObjectMass]
    double friction = 1.0;  ///< in [0, 1]
};

/// A static hollow tube lying along its local +x: a regular polygon of `sides` flat walls whose
/// inscribed circle has `radius`, one wall flat at the bottom.
struct PipeSpec {
    double radius = 0.08;     ///< inner radius (of the inscribed circle), m, > 0
    double thickness = 0.01;  ///< wall thickness, m, > 0
    double length = 1.0;      ///< m, > 0
    int sides = 24;           ///< number of walls around, in [3, 256]
    Vec3 position;            ///< centre of the entrance (the end at local x = 0), on the axis, m
    double yaw = 0;           ///< rad about +z; 0: runs towards +x
    double friction = 1.0;    ///< in [0, 1]
};

/// A static field of `count` random boxes ("stones") standing on the ground, drawn from `seed`:
/// each has its centre uniformly inside length × width, a random yaw, sides uniform in
/// [min_size, max_size] and height uniform in [min_height, max_height]. The same seed always
/// gives the same stones.
struct RubbleSpec {
    double length = 1.0;       ///< area along its local x, m, > 0
    double width = 1.0;        ///< area along its local y, m, > 0
    int count = 50;            ///< number of stones, in [0, 100000]
    double min_size = 0.02;    ///< m, > 0
    double max_size = 0.06;    ///< m, >= min_size
    double min_height = 0.01;  ///< m, > 0
    double max_height = 0.03;  ///< m, >= min_height
    std::uint64_t seed = 1;    ///< which stones: the same seed, the same stones
    Vec3 position;             ///< centre of the area on the ground, world frame, m
    double yaw = 0;            ///< rad about +z
    double friction = 1.0;     ///< in [0, 1]
};

/// A static terrain: heights over a length × width grid centred on `position`. The heights are
/// either stored (`heights`, e.g. sampled from a function) or read from a PNG image at compile
/// time (`image`: grey level 0 is height 0, white is max_height; the top row of the image is the
/// +y edge, its left column the −x edge).
struct HeightfieldSpec {
    double length = 1.0;  ///< extent along its local x, m, > 0
    double width = 1.0;   ///< extent along its local y, m, > 0
    int samples_x = 0;    ///< grid points along x, in [2, 4096] (0 with an image)
    int samples_y = 0;    ///< grid points along y, in [2, 4096] (0 with an image)
    /// heights, m, samples_x · samples_y values; point (i, j) is heights[j · samples_x + i] at
    /// x = −length/2 + i · length/(samples_x − 1), y = −width/2 + j · width/(samples_y − 1)
    std::vector<double> heights;
    std::string image;        ///< PNG file, used when `heights` is empty
    double max_height = 0.1;  ///< height of a white pixel, m, > 0 (images only)
    Vec3 position;            ///< centre of the grid at height 0, world frame, m
    double yaw = 0;           ///< rad about +z
    double friction = 1.0;    ///< in [0, 1]
};

/// A robot placed in a world, with the controllers that drive its joint groups.
struct PlacedRobot {
    RobotSpec robot;
    Pose pose;  ///< robot frame in the world frame (identity: tail at the origin, along +x)
    Actuation actuation;
};

/// Everything the physics needs to build a scene. Objects of each kind are numbered from 1 in
/// the order of their vector ("stairs 2").
struct WorldSpec {
    Vec3 gravity{0, 0, -9.81};  ///< m/s²
    FloorSpec floor;
    std::vector<BoxSpec> boxes;
    std::vector<WallSpec> walls;
    std::vector<RampSpec> ramps;
    std::vector<StairsSpec> stairs;
    std::vector<CylinderSpec> cylinders;
    std::vector<PipeSpec> pipes;
    std::vector<RubbleSpec> rubble;
    std::vector<HeightfieldSpec> heightfields;
    std::vector<PlacedRobot> robots;
};

/// Checks one object; `number` (from 1) names it in messages, e.g. "stairs 2 step_height must be
/// positive (got -0.01 m)". Throws SpecError. A heightfield's image is not read here.
void validate(const BoxSpec& box, int number);
void validate(const WallSpec& wall, int number);
void validate(const RampSpec& ramp, int number);
void validate(const StairsSpec& stairs, int number);
void validate(const CylinderSpec& cylinder, int number);
void validate(const PipeSpec& pipe, int number);
void validate(const RubbleSpec& rubble, int number);
void validate(const HeightfieldSpec& heightfield, int number);

/// How many rigid bodies the objects of `world` expand into (stairs: one per step, pipes: one
/// per side, rubble: one per stone, everything else one), without expanding them.
long long solid_count(const WorldSpec& world);

/// Checks a world spec (gravity, floor, every object, robots, the limits above); throws
/// SpecError.
void validate(const WorldSpec& world);

}  // namespace gaitlab
