// gaitlab.actuation: actuation specs (which controller drives which joint group, with which
// parameter values), read from and written to actuation files, taken from a robot's live
// controllers and applied to a robot.
#include <fmt/format.h>

#include "config_files.h"
#include "gaitlab/files.h"
#include "lua_util.h"
#include "recording.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

ActuationSpec& check_actuation(lua_State* L, int index) {
    return check_object<ActuationSpec>(L, index, kActuationType);
}

// gaitlab.actuation.load(path): the actuation file's spec, or nil and a message
int actuation_load(lua_State* L) {
    return protect(L, [&] {
        const std::string arg = check_string(L, 1);
        return file_read(L, [&] {
            new_object<ActuationSpec>(L, kActuationType,
                                      read_actuation(checked_input_path(L, arg)));
        });
    });
}

// act:save(path): writes the actuation file; the path, or nil and a message
int actuation_save(lua_State* L) {
    return protect(L, [&] {
        const ActuationSpec& a = check_actuation(L, 1);
        const ScriptPath path(L, check_string(L, 2));
        return file_written(L, path,
                            [&] { write_actuation(path.path(), relative_to(a, path.path())); });
    });
}

// act:groups(): { { joints = "pitch" | {1, 3}, controller = { builtin|file|template = name,
// params = { name = value } } }, ... }
int actuation_groups(lua_State* L) {
    return protect(L, [&] {
        const ActuationSpec& a = check_actuation(L, 1);
        lua_createtable(L, static_cast<int>(a.groups.size()), 0);
        for (size_t i = 0; i < a.groups.size(); ++i) {
            const GroupSpec& g = a.groups[i];
            lua_createtable(L, 0, 2);
            if (!g.role.empty()) {
                lua_pushstring(L, g.role.c_str());
            } else {
                lua_createtable(L, static_cast<int>(g.joints.size()), 0);
                for (size_t k = 0; k < g.joints.size(); ++k) {
                    lua_pushinteger(L, g.joints[k] + 1);
                    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
                }
            }
            lua_setfield(L, -2, "joints");
            lua_createtable(L, 0, 2);
            lua_pushstring(L, g.controller.name.c_str());
            lua_setfield(L, -2, to_string(g.controller.kind));
            lua_createtable(L, 0, static_cast<int>(g.controller.params.size()));
            for (const auto& [name, value] : g.controller.params) {
                lua_pushnumber(L, value);
                lua_setfield(L, -2, name.c_str());
            }
            lua_setfield(L, -2, "params");
            lua_setfield(L, -2, "controller");
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

int actuation_len(lua_State* L) {
    return protect(L, [&] {
        lua_pushinteger(L, static_cast<lua_Integer>(check_actuation(L, 1).groups.size()));
        return 1;
    });
}

int actuation_tostring(lua_State* L) {
    return protect(L, [&] {
        lua_pushfstring(L, "gaitlab.Actuation (%d groups)",
                        static_cast<int>(check_actuation(L, 1).groups.size()));
        return 1;
    });
}

}  // namespace

void open_actuation(lua_State* L) {
    const luaL_Reg methods[] = {
        {"save", actuation_save}, {"groups", actuation_groups}, {nullptr, nullptr}};
    const luaL_Reg meta[] = {
        {"__len", actuation_len}, {"__tostring", actuation_tostring}, {nullptr, nullptr}};
    register_type<ActuationSpec>(L, kActuationType, methods, meta);

    lua_newtable(L);
    lua_pushcfunction(L, actuation_load);
    lua_setfield(L, -2, "load");
    lua_setfield(L, -2, "actuation");
}

}  // namespace gaitlab::scripting
