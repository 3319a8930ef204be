// World geometry: the world library's objects expanded into primitive solids (boxes, cylinders,
// convex polyhedra, height grids). Compiling a simulation builds its rigid bodies from these;
// pictures and viewers draw their triangles. Specs are never expanded in place: a staircase stays
// a step count and sizes in its spec and becomes boxes only here.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gaitlab/robot.h"
#include "gaitlab/types.h"
#include "gaitlab/world.h"

namespace gaitlab {

/// Heights over a grid of samples_x × samples_y points spread evenly over length × width and
/// centred on the origin; point (i, j) is heights[j · samples_x + i] (see HeightfieldSpec).
struct HeightGrid {
    double length = 0;  ///< m
    double width = 0;   ///< m
    int samples_x = 0;
    int samples_y = 0;
    std::vector<double> heights;  ///< m

    double at(int i, int j) const {
        return heights[static_cast<size_t>(j) * static_cast<size_t>(samples_x) +
                       static_cast<size_t>(i)];
    }
};

/// The grid of heightfield `number` (from 1, for messages): its stored heights, or its PNG image
/// read now and scaled to max_height. Throws SpecError naming the image's path if it cannot be
/// read ("heightfield 1 cannot read image 'terrain.png': no such file").
HeightGrid height_grid(const HeightfieldSpec& heightfield, int number = 1);

/// One primitive rigid solid, in the world frame.
struct Solid {
    enum class Kind {
        box,          ///< `size`: full extents
        cylinder,     ///< axis along the local x; `size`: length, diameter, diameter
        convex,       ///< the convex hull of `points`, with `faces` for drawing
        heightfield,  ///< `grid`, centred on the pose's origin, heights along the local z
    };
    Kind kind = Kind::box;
    std::string object;        ///< what it belongs to: "ramp 1", "rubble 2", "snake tail" ...
    Pose pose;                 ///< its local frame in the world frame
    Vec3 size;                 ///< m (box, cylinder)
    std::vector<Vec3> points;  ///< convex: vertices in the local frame, m
    std::vector<std::vector<int>> faces;  ///< convex: vertex indices, counter-clockwise outside
    HeightGrid grid;                      ///< heightfield
    double mass = 0;                      ///< kg (0: static)
    double friction = 1.0;                ///< in [0, 1]
    /// kg·m², principal moments about the local axes (a robot body's given inertia); none: the
    /// shape's, from its size and mass
    std::optional<Vec3> inertia;
    /// m, the centre of mass in the local frame (a robot body's given one); none: the origin
    std::optional<Vec3> center_of_mass;
};

/// The objects of `world` (boxes, walls, ramps, stairs, cylinders, pipes, rubble, heightfields,
/// in that order, each kind in spec order) as solids; not the floor, not the robots. Reads
/// heightfield images; throws SpecError if one cannot be read.
std::vector<Solid> world_solids(const WorldSpec& world);

/// Body `body` of `robot` as a solid at `pose` (world frame), named "ROBOT BODY".
Solid body_solid(const RobotSpec& robot, int body, const Pose& pose);

/// A triangle, corners counter-clockwise seen from outside, m.
struct Triangle {
    Vec3 a, b, c;
};

/// The surface of a solid as triangles in the world frame (cylinders with `segments` sides; a
/// heightfield as its top surface, two triangles per grid cell).
std::vector<Triangle> triangles(const Solid& solid, int segments = 24);

}  // namespace gaitlab
