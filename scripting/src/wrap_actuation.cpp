// gaitlab.actuation: actuation specs (which controller drives which joint group, with which
// parameter values), read from and written to actuation files, taken from a robot's live
// controllers and applied to a robot.
#include <algorithm>

#include <fmt/format.h>

#include "config_files.h"
#include "gaitlab/files.h"
#include "gaitlab/robot.h"
#include "gaitlab/xml.h"
#include "lua_util.h"
#include "recording.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

ActuationSpec& check_actuation(lua_State* L, int index) {
    return check_object<ActuationSpec>(L, index, kActuationType);
}

// one group of gaitlab.actuation{ groups = {...} } at the top of the stack, as a file's <group>
GroupSpec read_group(lua_State* L) {
    GroupSpec g;
    const Fields f(L, -1, 1, {"joints", "controller"});
    const int jt = f.push("joints");
    std::string text;
    if (jt == LUA_TSTRING) {
        text = to_string(L, -1);
    } else if (jt == LUA_TTABLE) {
        const auto n = static_cast<lua_Integer>(lua_rawlen(L, -1));
        for (lua_Integer i = 1; i <= n; ++i) {
            lua_rawgeti(L, -1, i);
            lua_Integer j = 0;
            const bool ok = read_integer(L, -1, j).empty();
            lua_pop(L, 1);
            if (!ok) {
                lua_pop(L, 1);
                f.fail("joints", fmt::format("entry {} is not a joint number", i));
            }
            text += (text.empty() ? "" : " ") + std::to_string(j);
        }
    } else {
        const std::string t = type_name(L, -1);
        lua_pop(L, 1);
        f.fail("joints",
               "a role ('pitch', 'yaw', 'all') or a list of joint numbers expected, got " + t);
    }
    lua_pop(L, 1);
    try {
        parse_group_joints(text, g);
    } catch (const SpecError& e) {
        f.fail("joints", e.what());
    }
    if (f.push("controller") != LUA_TTABLE) {
        const std::string t = type_name(L, -1);
        lua_pop(L, 1);
        f.fail("controller",
               "table expected ({ builtin|file|template = name, params = {...} }), got " + t);
    }
    const Fields c(L, -1, 1, {"builtin", "file", "template", "params"});
    int kinds = 0;
    const char* names[] = {"builtin", "file", "template"};
    for (int k = 0; k < 3; ++k) {
        if (!c.has(names[k])) continue;
        ++kinds;
        g.controller.kind = static_cast<ControllerRef::Kind>(k);
        g.controller.name = c.string(names[k], "");
        if (g.controller.name.empty()) {
            lua_pop(L, 1);
            f.fail("controller", fmt::format("'{}' is empty", names[k]));
        }
        // a Lua controller file is relative to the script, as every path a script gives
        if (k == 1) g.controller.name = script_path(L, g.controller.name);
    }
    if (kinds != 1) {
        lua_pop(L, 1);
        f.fail("controller",
               "exactly one of 'builtin', 'file' or 'template' expected (which controller)");
    }
    const int pt = c.push("params");
    if (pt == LUA_TTABLE) {
        lua_pushnil(L);
        while (lua_next(L, -2) != 0) {
            int ok = 0;
            const double v = lua_tonumberx(L, -1, &ok);
            if (lua_type(L, -2) != LUA_TSTRING) {
                lua_pop(L, 4);
                f.fail("controller", "params: { name = number, ... } expected (named values)");
            }
            if (!ok) {
                const std::string message = fmt::format("params: '{}' must be a number, got {}",
                                                        to_string(L, -2), type_name(L, -1));
                lua_pop(L, 4);
                f.fail("controller", message);
            }
            g.controller.params.emplace_back(to_string(L, -2), v);
            lua_pop(L, 1);
        }
        // in name order: a table has none of its own
        std::sort(g.controller.params.begin(), g.controller.params.end());
    } else if (pt != LUA_TNIL) {
        const std::string t = type_name(L, -1);
        lua_pop(L, 2);
        f.fail("controller", "params: { name = number, ... } expected, got " + t);
    }
    lua_pop(L, 2);
    return g;
}

// gaitlab.actuation{ groups = { { joints =, controller = }, ... } }: an actuation spec, as an
// actuation file says it (parameter names are checked when a robot is actuated with it)
int actuation_new(lua_State* L) {
    // called as gaitlab.actuation{...}: argument 1 is the gaitlab.actuation table itself
    return protect(L, [&] {
        const Fields f(L, 2, 1, {"groups"});
        ActuationSpec a;
        const int t = f.push("groups");
        if (t != LUA_TTABLE) {
            const std::string n = type_name(L, -1);
            lua_pop(L, 1);
            f.fail("groups", "list of groups expected, got " + n);
        }
        const int list = lua_gettop(L);
        const auto n = static_cast<lua_Integer>(lua_rawlen(L, list));
        if (n > kMaxRobotBodies) {
            lua_pop(L, 1);
            f.fail("groups", fmt::format("an actuation has at most {} groups", kMaxRobotBodies));
        }
        for (lua_Integer i = 1; i <= n; ++i) {
            const std::string prefix = fmt::format("groups[{}]: ", i);
            if (lua_rawgeti(L, list, i) != LUA_TTABLE) {
                const std::string tn = type_name(L, -1);
                lua_settop(L, list - 1);
                throw ArgError(1, prefix + "table expected, got " + tn);
            }
            try {
                a.groups.push_back(read_group(L));
            } catch (const ArgError& e) {
                lua_settop(L, list - 1);
                throw ArgError(1, prefix + e.what());
            }
            lua_pop(L, 1);
        }
        lua_pop(L, 1);
        new_object<ActuationSpec>(L, kActuationType, std::move(a));
        return 1;
    });
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
        const size_t n = check_actuation(L, 1).groups.size();
        lua_pushfstring(L, "gaitlab.Actuation (%d group%s)", static_cast<int>(n),
                        n == 1 ? "" : "s");
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
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, actuation_new);
    lua_setfield(L, -2, "__call");
    lua_setmetatable(L, -2);
    lua_pushcfunction(L, actuation_load);
    lua_setfield(L, -2, "load");
    lua_setfield(L, -2, "actuation");
}

}  // namespace gaitlab::scripting
