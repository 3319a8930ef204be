#include "stdlib.h"

#include <cstring>

#include "gaitlab/scripting/lua_host.h"
#include "stdlib_sources.h"
#include "template_sources.h"

namespace gaitlab::scripting {

void open_stdlib(lua_State* L, int gaitlab_index) {
    for (const StdlibSource* s = kStdlibSources; s->name; ++s) {
        // "=": a name, not a file, so paths in calls from it are not relative to it
        const std::string chunk = std::string("=stdlib/") + s->name;
        if (luaL_loadbufferx(L, s->code, std::strlen(s->code), chunk.c_str(), "t") != LUA_OK) {
            lua_error(L);  // a broken stdlib is a build defect; report it as Lua would
        }
        lua_pushvalue(L, gaitlab_index);
        lua_pushvalue(L, LUA_REGISTRYINDEX);
        lua_call(L, 2, 0);
    }
}

const StdlibSource* controller_templates() {
    return kTemplateSources;
}

}  // namespace gaitlab::scripting
