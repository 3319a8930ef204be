// The gaitlab Lua module. This list of open_* calls is the map of the Lua API: each binding
// file adds its part to the gaitlab table, then the Lua standard library of gaitlab (stdlib/)
// adds the parts written in Lua.
#include <lua.hpp>

#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/version.h"
#include "guard.h"
#include "lua_util.h"
#include "sandbox.h"
#include "stdlib.h"
#include "wrap.h"

using namespace gaitlab::scripting;

extern "C" int luaopen_gaitlab(lua_State* L) {
    Guard::install(L);  // budgets and interrupts, before any code of gaitlab's runs
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
    guard_patterns(L);   // what sandboxes copy (after open_simulation's print), guarded

    open_stdlib(L, lua_gettop(L));  // vec3.lua, worlds.lua (gaitlab.worlds) ...
    return 1;
}
