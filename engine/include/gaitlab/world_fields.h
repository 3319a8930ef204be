// The fields of the world library's objects (walls, ramps, stairs, cylinders, pipes, rubble,
// heightfields), each kind's in the order environment files write them, with their units: the
// one list that the environment file's reader and writer and the viewer's editor walk, so that
// they name the same fields alike. A box is not here: files give it a yaw or a quaternion and a
// position whose default depends on its size, so each reads and writes it its own way.
#pragma once

#include "gaitlab/world.h"

namespace gaitlab {

namespace world_fields_detail {

// where the kinds placed by a position and a yaw about z stand
template <class V, class S>
void placed(V& v, S& s) {
    v.vec3("position", s.position, "m");
    v.angle("yaw", s.yaw);
}

}  // namespace world_fields_detail

/// Walks the fields of `s` (a spec of the kind the null pointer's type names, const or not) with
/// `v`, which has number(name, double, unit), vec3(name, Vec3, unit), angle(name, double: rad;
/// files and forms give degrees), count(name, int, min, max), seed(name, std::uint64_t) and
/// flag(name, bool); `name` is the file's attribute, `unit` "m", "kg" or "" (none).
template <class V, class S>
void world_object_fields(V& v, S& s, WallSpec*) {
    v.number("length", s.length, "m");
    v.number("height", s.height, "m");
    v.number("thickness", s.thickness, "m");
    world_fields_detail::placed(v, s);
    v.number("friction", s.friction, "");
}

template <class V, class S>
void world_object_fields(V& v, S& s, RampSpec*) {
    v.angle("slope", s.slope);
    v.number("length", s.length, "m");
    v.number("width", s.width, "m");
    world_fields_detail::placed(v, s);
    v.number("friction", s.friction, "");
}

template <class V, class S>
void world_object_fields(V& v, S& s, StairsSpec*) {
    v.count("steps", s.steps, 1, kMaxStairsSteps);
    v.number("step_height", s.step_height, "m");
    v.number("step_depth", s.step_depth, "m");
    v.number("width", s.width, "m");
    v.number("landing", s.landing, "m");
    world_fields_detail::placed(v, s);
    v.number("friction", s.friction, "");
}

template <class V, class S>
void world_object_fields(V& v, S& s, CylinderSpec*) {
    v.number("radius", s.radius, "m");
    v.number("length", s.length, "m");
    v.flag("lying", s.lying);
    world_fields_detail::placed(v, s);
    v.number("mass", s.mass, "kg");
    v.number("friction", s.friction, "");
}

template <class V, class S>
void world_object_fields(V& v, S& s, PipeSpec*) {
    v.number("radius", s.radius, "m");
    v.number("thickness", s.thickness, "m");
    v.number("length", s.length, "m");
    v.count("sides", s.sides, 3, kMaxPipeSides);
    world_fields_detail::placed(v, s);
    v.number("friction", s.friction, "");
}

template <class V, class S>
void world_object_fields(V& v, S& s, RubbleSpec*) {
    v.number("length", s.length, "m");
    v.number("width", s.width, "m");
    v.count("count", s.count, 0, kMaxRubbleCount);
    v.number("min_size", s.min_size, "m");
    v.number("max_size", s.max_size, "m");
    v.number("min_height", s.min_height, "m");
    v.number("max_height", s.max_height, "m");
    v.seed("seed", s.seed);
    world_fields_detail::placed(v, s);
    v.number("friction", s.friction, "");
}

/// A heightfield's scalar fields; its heights (an image, or a grid the file stores) go beside
/// them.
template <class V, class S>
void world_object_fields(V& v, S& s, HeightfieldSpec*) {
    v.number("length", s.length, "m");
    v.number("width", s.width, "m");
    v.number("max_height", s.max_height, "m");
    world_fields_detail::placed(v, s);
    v.number("friction", s.friction, "");
}

}  // namespace gaitlab
