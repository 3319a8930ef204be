// What an optimization spec measures: its `fitness` field read and checked, and the Lua chunk
// that runs an evaluation's simulation and computes the fitness (docs/optimization.md,
// "Fitness").
#pragma once

#include <lua.hpp>

#include <string>

namespace gaitlab::optimize {
struct Spec;
}

namespace gaitlab::optimize::detail {

/// Reads the `fitness` field, on top of L's stack, into spec.fitness (and spec.direction).
/// Throws SpecError "FILE: fitness: ..." naming what is expected.
void read_fitness(lua_State* L, Spec& spec);

/// Reads the `worlds` and `seeds` fields of the spec table on top of L's stack into spec.
/// Throws SpecError "FILE: worlds: ..." naming what is expected.
void read_cases(lua_State* L, Spec& spec);

/// The measuring chunk's text. Called with (sim, settle, duration, kind, robot, fitness, p,
/// dx, dy), it runs settle, then duration, and returns the fitness; its errors have no
/// position (level 0).
const char* measure_chunk();

}  // namespace gaitlab::optimize::detail
