// gaitlab/core.so: gaitlab for the Lua 5.4 interpreter that loads it (gaitlab.so, next to it,
// checks the Lua version first). It is the scripting sources linked without a Lua core: the
// interpreter's C Lua runs them (scripting/src/lua_util.h says what that takes), in a state
// that is the interpreter's, not gaitlab's (StateOwner::interpreter: no memory limit, the
// interpreter's globals, hooks and signals left as they are; docs/embedding.md).
#include <lua.hpp>

#include "wrap.h"

extern "C" __attribute__((visibility("default"))) int luaopen_gaitlab_core(lua_State* L) {
    return gaitlab::scripting::open_gaitlab(L, gaitlab::scripting::StateOwner::interpreter);
}
