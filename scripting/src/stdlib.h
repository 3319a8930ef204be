// gaitlab's Lua standard library, embedded in the binary at build time from stdlib/*.lua.
#pragma once

#include <lua.hpp>

namespace gaitlab::scripting {

/// Runs every stdlib chunk with (gaitlab table, registry) as its arguments; the registry holds
/// "gaitlab.closest" (did-you-mean) and "gaitlab.world_sources" (worlds/*.lua by name).
void open_stdlib(lua_State* L, int gaitlab_index);

}  // namespace gaitlab::scripting
