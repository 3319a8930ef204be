// Specs built from a simulation file: `simulation = "walk.xml"` (or a Lua file returning a
// simulation) and `set = { amplitude = "sine.amplitude", ... }` in place of a build function
// (docs/optimization.md, "A spec from a simulation file").
#pragma once

#include <string>

namespace gaitlab::scripting {
class LuaHost;
}

namespace gaitlab::optimize::detail {

/// When the spec table on top of `host`'s stack names a `simulation` file, checks it and its
/// `set` field (the file loads, every controller and parameter exists, each range lies inside
/// the controller parameter's) and makes the table's `build` a function that loads the file
/// and sets the controllers' parameters. Throws SpecError "FILE: FIELD: ..." otherwise; does
/// nothing for a spec without `simulation`.
void install_simulation_build(scripting::LuaHost& host, const std::string& file);

}  // namespace gaitlab::optimize::detail
