// The gaitlab Lua module. This list of open_* calls is the map of the Lua API: each binding
// file adds its part to the gaitlab table, then the Lua standard library of gaitlab (stdlib/)
// adds the parts written in Lua.
//
// Two entries open it: luaopen_gaitlab (here), for a state a LuaHost owns (gaitlab run, the
// console, programs linking gaitlab::scripting), and luaopen_gaitlab_core, for the state of a
// Lua interpreter that does `require "gaitlab"` (scripting/module/core.cpp: the module
// gaitlab.so loads it from gaitlab/core.so). They differ only in what they take from the state:
// see StateOwner.
#include <lua.hpp>

#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/version.h"
#include "guard.h"
#include "lua_util.h"
#include "sandbox.h"
#include "stdlib.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

// registry key of the gaitlab table once made: opening gaitlab again in the same state gives
// the same table (and keeps the guard, reloader and recordings its simulations hold)
constexpr const char* kModuleKey = "gaitlab.module";

}  // namespace

int open_gaitlab(lua_State* L, StateOwner owner) {
    return protect(L, [&] {
        if (lua_getfield(L, LUA_REGISTRYINDEX, kModuleKey) == LUA_TTABLE) return 1;
        lua_pop(L, 1);
        Guard::install(L, owner);  // budgets and interrupts, before any code of gaitlab's runs
        lua_newtable(L);
        lua_pushstring(L, gaitlab::version());
        lua_setfield(L, -2, "version");
        luaL_newmetatable(L, "gaitlab.Vec3");  // filled in by stdlib/vec3.lua
        lua_pop(L, 1);

        open_module(L);      // gaitlab.module, gaitlab.modules
        open_robot(L);       // gaitlab.robot
        open_world(L);       // gaitlab.world
        open_controller(L);  // gaitlab.controllers, gaitlab.controller
        open_actuation(L);   // gaitlab.actuation
        open_sensor(L);      // gaitlab.sensor, robot:sensor{...}
        open_simulation(L);  // gaitlab.simulation (and the recordings)
        open_data(L);        // gaitlab.data
        open_optimize(L);    // gaitlab.optimize (after open_simulation: its handler)
        guard_patterns(L);   // what sandboxes copy (after open_simulation's print), guarded

        open_stdlib(L, lua_gettop(L));  // vec3.lua, worlds.lua (gaitlab.worlds) ...
        lua_pushvalue(L, -1);
        lua_setfield(L, LUA_REGISTRYINDEX, kModuleKey);
        return 1;
    });
}

}  // namespace gaitlab::scripting

extern "C" int luaopen_gaitlab(lua_State* L) {
    return gaitlab::scripting::open_gaitlab(L, gaitlab::scripting::StateOwner::gaitlab);
}
