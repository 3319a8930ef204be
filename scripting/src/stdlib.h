// gaitlab's Lua standard library, embedded in the binary at build time from stdlib/*.lua, and
// the controller templates from stdlib/templates/*.lua.
#pragma once

#include <lua.hpp>

namespace gaitlab::scripting {

/// One embedded Lua file: its name ("vec3.lua") and its text.
struct StdlibSource {
    const char* name;
    const char* code;
};

/// Runs every stdlib chunk with (gaitlab table, registry) as its arguments; the registry holds
/// "gaitlab.closest" (did-you-mean) and "gaitlab.world_sources" (worlds/*.lua by name).
void open_stdlib(lua_State* L, int gaitlab_index);

/// The embedded controller templates, ending with {nullptr, nullptr}.
const StdlibSource* controller_templates();

}  // namespace gaitlab::scripting
