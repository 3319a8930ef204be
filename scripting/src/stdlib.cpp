#include "stdlib.h"

#include <cstring>
#include <string>

#include "gaitlab/scripting/lua_host.h"
#include "lua_util.h"
#include "stdlib_sources.h"
#include "template_sources.h"
#include "world_sources.h"

namespace gaitlab::scripting {

namespace {

// closest(word, {candidates}): the candidate nearest to word, or nil (see lua_util.h)
int lua_closest(lua_State* L) {
    return protect(L, [&] {
        const std::string word = check_string(L, 1);
        check_table(L, 2);
        std::vector<std::string> candidates;
        for (lua_Integer i = 1; lua_rawgeti(L, 2, i) == LUA_TSTRING; ++i) {
            candidates.emplace_back(to_string(L, -1));
            lua_pop(L, 1);
        }
        lua_pop(L, 1);
        const std::string c = closest(word, candidates);
        if (c.empty()) {
            lua_pushnil(L);
        } else {
            lua_pushstring(L, c.c_str());
        }
        return 1;
    });
}

}  // namespace

void open_stdlib(lua_State* L, int gaitlab_index) {
    // what the stdlib's chunks find in the registry: C++ mechanics they build on, and the
    // sources of worlds/*.lua by name
    lua_pushcfunction(L, lua_closest);
    lua_setfield(L, LUA_REGISTRYINDEX, "gaitlab.closest");
    lua_newtable(L);
    for (const StdlibSource* s = kWorldSources; s->name; ++s) {
        const std::string name(s->name, std::strlen(s->name) - 4);  // without ".lua"
        lua_pushstring(L, s->code);
        lua_setfield(L, -2, name.c_str());
    }
    lua_setfield(L, LUA_REGISTRYINDEX, "gaitlab.world_sources");

    for (const StdlibSource* s = kStdlibSources; s->name; ++s) {
        // "=": a name, not a file, so paths in calls from it are not relative to it
        const std::string chunk = std::string("=stdlib/") + s->name;
        if (luaL_loadbufferx(L, s->code, std::strlen(s->code), chunk.c_str(), "t") != LUA_OK) {
            // a broken stdlib is a build defect; report it as Lua would
            const std::string message = to_string(L, -1);
            lua_pop(L, 1);
            throw ScriptError(message, chunk.substr(1), 0, "");
        }
        lua_pushvalue(L, gaitlab_index);
        lua_pushvalue(L, LUA_REGISTRYINDEX);
        protected_call(L, 2, 0);
    }
}

const StdlibSource* controller_templates() {
    return kTemplateSources;
}

}  // namespace gaitlab::scripting
