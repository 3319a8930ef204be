// gaitlab.controllers (built in), gaitlab.controller{...} (Lua classes), controller handles.
#include <filesystem>
#include <string_view>

#include <fmt/format.h>

#include "gaitlab/controllers/registry.h"
#include "gaitlab/files.h"
#include "hot_reload.h"
#include "lua_controller.h"
#include "lua_util.h"
#include "scene.h"
#include "stdlib.h"
#include "wrap.h"

namespace gaitlab::scripting {

HandleKey handle_key(const ControllerHandle& c) {
    return {c.controller.get(), ""};
}

namespace {

using ClassPtr = std::shared_ptr<LuaControllerClass>;

Controller& check_controller(lua_State* L, int index) {
    return *check_object<ControllerHandle>(L, index, kControllerType).controller;
}

std::vector<std::string> param_names(const Controller& c) {
    std::vector<std::string> names;
    for (const ParamDef& p : c.def().params)
        names.push_back(p.name);
    return names;
}

// sets the parameters given in the table at `index` (argument `arg`); unknown names and values
// out of range are errors
void apply_params(lua_State* L, int index, int arg, Controller& c) {
    if (lua_isnoneornil(L, index)) return;
    if (!lua_istable(L, index)) throw ArgError(arg, "table expected, got " + type_name(L, index));
    const std::vector<std::string> names = param_names(c);
    lua_pushnil(L);
    while (lua_next(L, index) != 0) {
        if (lua_type(L, -2) != LUA_TSTRING) {
            throw ArgError(arg, "unexpected " + type_name(L, -2) + " key (fields are named)");
        }
        const std::string key = to_string(L, -2);
        const int i = c.find_param(key);
        if (i < 0) {
            throw ArgError(arg,
                           fmt::format("unknown key '{}'{} (parameters of '{}': {})", key,
                                       did_you_mean(key, names), c.name(), fmt::join(names, ", ")));
        }
        int ok = 0;
        const double v = lua_tonumberx(L, -1, &ok);
        if (!ok) {
            throw ArgError(
                arg, fmt::format("field '{}': number expected, got {}", key, type_name(L, -1)));
        }
        try {
            c.set_param(i, v);
        } catch (const SpecError& e) {
            throw ArgError(arg, e.what());
        }
        lua_pop(L, 1);
    }
}

void push_handle(lua_State* L, std::shared_ptr<Controller> c) {
    push_controller(L, std::move(c), false);
}

// gaitlab.controllers.<name>{params}: upvalue 1 is the built-in's name
int builtin_new(lua_State* L) {
    return protect(L, [&] {
        const char* name = lua_tostring(L, lua_upvalueindex(1));
        std::shared_ptr<Controller> c = controllers::make_builtin(name);
        apply_params(L, 1, 1, *c);
        push_handle(L, std::move(c));
        return 1;
    });
}

int controller_index(lua_State* L) {
    return protect(L, [&] {
        Controller& c = check_controller(L, 1);
        const std::string key = check_string(L, 2);
        const int i = c.find_param(key);
        if (i >= 0) {
            lua_pushnumber(L, c.param(i));
            return 1;
        }
        if (key == "name") {
            lua_pushstring(L, c.name().c_str());
            return 1;
        }
        if (key == "failed") {
            lua_pushboolean(L, c.failed());
            return 1;
        }
        if (key == "error") {
            if (c.failed()) {
                lua_pushstring(L, c.failure().c_str());
            } else {
                lua_pushnil(L);
            }
            return 1;
        }
        if (raw_getfield(L, lua_upvalueindex(1), key) != LUA_TNIL) return 1;
        std::vector<std::string> names = param_names(c);
        for (const char* m : {"name", "params", "values", "set", "failed", "error"})
            names.emplace_back(m);
        throw Error(fmt::format("controller '{}' has no parameter or method '{}'{}", c.name(), key,
                                did_you_mean(key, names)));
    });
}

int controller_eq(lua_State* L) {
    return handle_eq<ControllerHandle>(L, kControllerType);
}

int controller_newindex(lua_State* L) {
    return protect(L, [&] {
        Controller& c = check_controller(L, 1);
        const std::string key = check_string(L, 2);
        const int i = c.find_param(key);
        if (i < 0) {
            throw Error(fmt::format("controller '{}' has no parameter '{}'{}", c.name(), key,
                                    did_you_mean(key, param_names(c))));
        }
        int ok = 0;
        const double v = lua_tonumberx(L, 3, &ok);
        if (!ok) {
            throw Error(
                fmt::format("{}.{}: number expected, got {}", c.name(), key, type_name(L, 3)));
        }
        c.set_param(i, v, default_origin(L));
        return 0;
    });
}

// ctl:set(name, value [, origin]): a parameter change made by `origin` ("script", the default,
// "console" or "viewer"): front ends use it so that a replay can tell their changes apart
int controller_set(lua_State* L) {
    return protect(L, [&] {
        Controller& c = check_controller(L, 1);
        const std::string key = check_string(L, 2);
        const double v = check_number(L, 3);
        const Origin origin = opt_origin(L, 4);
        const int i = c.find_param(key);
        if (i < 0) {
            throw ArgError(2, fmt::format("controller '{}' has no parameter '{}'{}", c.name(), key,
                                          did_you_mean(key, param_names(c))));
        }
        c.set_param(i, v, origin);
        return 0;
    });
}

int controller_params(lua_State* L) {
    return protect(L, [&] {
        Controller& c = check_controller(L, 1);
        const auto& params = c.def().params;
        lua_createtable(L, 0, static_cast<int>(params.size()));
        for (size_t i = 0; i < params.size(); ++i) {
            const ParamDef& p = params[i];
            lua_createtable(L, 0, 5);
            lua_pushnumber(L, c.param(static_cast<int>(i)));
            lua_setfield(L, -2, "value");
            lua_pushnumber(L, p.default_value);
            lua_setfield(L, -2, "default");
            lua_pushnumber(L, p.min);
            lua_setfield(L, -2, "min");
            lua_pushnumber(L, p.max);
            lua_setfield(L, -2, "max");
            lua_pushstring(L, p.unit.c_str());
            lua_setfield(L, -2, "unit");
            lua_setfield(L, -2, p.name.c_str());
        }
        return 1;
    });
}

int controller_values(lua_State* L) {
    return protect(L, [&] {
        Controller& c = check_controller(L, 1);
        const auto& names = c.def().values;
        lua_createtable(L, 0, static_cast<int>(names.size()));
        for (size_t k = 0; k < names.size(); ++k) {
            const std::vector<double>& v = c.values(static_cast<int>(k));
            lua_createtable(L, static_cast<int>(v.size()), 0);
            for (size_t m = 0; m < v.size(); ++m) {
                lua_pushnumber(L, v[m]);
                lua_rawseti(L, -2, static_cast<lua_Integer>(m + 1));
            }
            lua_setfield(L, -2, names[k].c_str());
        }
        return 1;
    });
}

int controller_tostring(lua_State* L) {
    return protect(L, [&] {
        Controller& c = check_controller(L, 1);
        lua_pushfstring(L, "gaitlab.Controller '%s'", c.name().c_str());
        return 1;
    });
}

// one parameter declaration: { default, min = , max = , unit = }
ParamDef read_param(lua_State* L, int index, const std::string& name) {
    const std::string where = "params." + name;
    if (!lua_istable(L, index)) {
        throw ArgError(1, where + ": table expected ({default, min = , max = , unit = }), got " +
                              type_name(L, index));
    }
    ParamDef p;
    p.name = name;
    bool has_default = false, has_min = false, has_max = false;
    lua_pushnil(L);
    while (lua_next(L, index) != 0) {
        const bool positional = lua_type(L, -2) == LUA_TNUMBER && lua_tointeger(L, -2) == 1;
        const std::string key =
            positional ? "1" : (lua_type(L, -2) == LUA_TSTRING ? to_string(L, -2) : "?");
        if (key == "unit") {
            if (lua_type(L, -1) != LUA_TSTRING) {
                throw ArgError(1, where + ".unit: string expected, got " + type_name(L, -1));
            }
            p.unit = to_string(L, -1);
        } else if (key == "1" || key == "default" || key == "min" || key == "max") {
            int ok = 0;
            const double v = lua_tonumberx(L, -1, &ok);
            if (!ok) {
                throw ArgError(1, fmt::format("{}.{}: number expected, got {}", where,
                                              key == "1" ? "default" : key, type_name(L, -1)));
            }
            if (key == "min") {
                p.min = v;
                has_min = true;
            } else if (key == "max") {
                p.max = v;
                has_max = true;
            } else {
                p.default_value = v;
                has_default = true;
            }
        } else {
            throw ArgError(1, fmt::format("{}: unknown key '{}' (expected the default value "
                                          "first, then min, max, unit)",
                                          where, key));
        }
        lua_pop(L, 1);
    }
    if (!has_default) throw ArgError(1, where + ": default value expected as the first entry");
    if (!has_min || !has_max) throw ArgError(1, where + ": min and max expected");
    return p;
}

// an optional function field of gaitlab.controller{...}: a registry reference or LUA_NOREF
int optional_function(lua_State* L, const Fields& f, const char* key) {
    const int t = f.push(key);
    if (t == LUA_TNIL) {
        lua_pop(L, 1);
        return LUA_NOREF;
    }
    if (t != LUA_TFUNCTION) f.fail(key, "function expected, got " + type_name(L, -1));
    return luaL_ref(L, LUA_REGISTRYINDEX);
}

// gaitlab.controller{ name = , params = , values = , step = , snapshot = , on_reload = ,
// instruction_budget = }
int class_new(lua_State* L) {
    return protect(L, [&] {
        Fields f(
            L, 2, 1,
            {"name", "params", "values", "step", "snapshot", "on_reload", "instruction_budget"});
        auto cls = std::make_shared<LuaControllerClass>();
        if (!f.has("name")) f.fail("name", "string expected, got nil");
        cls->def.name = f.string("name", "");
        if (f.push("params") == LUA_TTABLE) {
            // declaration order is not kept by Lua tables: sort by name for a stable order
            std::vector<std::string> names;
            lua_pushnil(L);
            while (lua_next(L, -2) != 0) {
                lua_pop(L, 1);
                if (lua_type(L, -1) != LUA_TSTRING) f.fail("params", "parameter names expected");
                names.emplace_back(to_string(L, -1));
            }
            std::sort(names.begin(), names.end());
            for (const std::string& n : names) {
                raw_getfield(L, -1, n);
                cls->def.params.push_back(read_param(L, lua_gettop(L), n));
                lua_pop(L, 1);
            }
        } else if (!lua_isnil(L, -1)) {
            f.fail("params", "table expected, got " + type_name(L, -1));
        }
        lua_pop(L, 1);
        if (f.push("values") == LUA_TTABLE) {
            const auto n = static_cast<lua_Integer>(lua_rawlen(L, -1));
            for (lua_Integer i = 1; i <= n; ++i) {
                lua_rawgeti(L, -1, i);
                if (lua_type(L, -1) != LUA_TSTRING) f.fail("values", "list of names expected");
                cls->def.values.emplace_back(to_string(L, -1));
                lua_pop(L, 1);
            }
        } else if (!lua_isnil(L, -1)) {
            f.fail("values", "list of names expected, got " + type_name(L, -1));
        }
        lua_pop(L, 1);
        // names that self already holds for something else
        const auto check_free = [&](const char* field, const std::string& name) {
            if (name == "joints") f.fail(field, "'joints' is reserved (it holds the joint count)");
            for (const char* m : kControllerMethods) {
                if (name == m) {
                    f.fail(field,
                           fmt::format("'{}' is reserved (a method of every controller)", m));
                }
            }
        };
        for (const std::string& v : cls->def.values)
            check_free("values", v);
        for (const ParamDef& p : cls->def.params) {
            check_free("params", p.name);
            // a parameter reads and writes as a field of the controller's handle (ctl.amplitude):
            // one named as the handle's own fields and methods hid them (ctl.failed read 0)
            for (const char* h : {"name", "failed", "error", "params", "values", "set"}) {
                if (p.name == h) {
                    f.fail("params", fmt::format("'{}' is reserved (the controller handle's "
                                                 "ctl.{} would be hidden by it)",
                                                 h, h));
                }
            }
        }
        try {
            validate(cls->def);
        } catch (const SpecError& e) {
            throw ArgError(1, e.what());
        }
        if (f.push("step") != LUA_TFUNCTION) {
            f.fail("step", "function expected, got " + type_name(L, -1));
        }
        if (f.has("instruction_budget")) {
            const long long budget = f.integer("instruction_budget", kDefaultInstructionBudget);
            if (budget < 1 || budget > 0x7fffffff) {
                f.fail("instruction_budget", "integer in [1, 2147483647] expected");
            }
            cls->budget = budget;
        }
        cls->step_ref = luaL_ref(L, LUA_REGISTRYINDEX);
        cls->snapshot_ref = optional_function(L, f, "snapshot");
        cls->on_reload_ref = optional_function(L, f, "on_reload");
        lua_Debug ar;
        if (lua_getstack(L, 1, &ar) && lua_getinfo(L, "Sl", &ar)) {
            cls->file = ar.source[0] == '@' ? ar.source + 1 : ar.short_src;
            cls->line = ar.currentline;
        }
        new_object<ClassPtr>(L, kControllerClassType, std::move(cls));
        return 1;
    });
}

// cls{params}: a new instance
int class_call(lua_State* L) {
    return protect(L, [&] {
        ClassPtr cls = check_object<ClassPtr>(L, 1, kControllerClassType);
        auto c = std::make_shared<LuaController>(L, cls);
        apply_params(L, 2, 1, *c);
        push_handle(L, std::move(c));
        return 1;
    });
}

int class_index(lua_State* L) {
    return protect(L, [&] {
        ClassPtr& cls = check_object<ClassPtr>(L, 1, kControllerClassType);
        const std::string key = lua_type(L, 2) == LUA_TSTRING ? to_string(L, 2) : "";
        if (key == "name") {
            lua_pushstring(L, cls->def.name.c_str());
        } else if (key == "file") {
            lua_pushstring(L, cls->file.c_str());
        } else if (key == "version") {
            lua_pushinteger(L, static_cast<lua_Integer>(cls->version));
        } else if (key == "reload_error") {
            if (cls->reload_error.empty()) {
                lua_pushnil(L);
            } else {
                lua_pushstring(L, cls->reload_error.c_str());
            }
        } else if (key == "instruction_budget") {
            lua_pushinteger(L, static_cast<lua_Integer>(cls->budget));
        } else {
            lua_pushnil(L);
        }
        return 1;
    });
}

int class_tostring(lua_State* L) {
    return protect(L, [&] {
        ClassPtr& cls = check_object<ClassPtr>(L, 1, kControllerClassType);
        lua_pushfstring(L, "gaitlab.ControllerClass '%s'", cls->def.name.c_str());
        return 1;
    });
}

// the folder a sandboxed file's gaitlab.controller may write in (upvalue 1), or nullptr when a
// script calls
const char* sandbox_folder(lua_State* L) {
    return lua_type(L, lua_upvalueindex(1)) == LUA_TSTRING ? lua_tostring(L, lua_upvalueindex(1))
                                                           : nullptr;
}

// whether `path` lies inside the sandbox's `folder`, links resolved (folders that do not exist
// yet are taken as the system will resolve them); the folder, absolute, in `root`
bool inside_sandbox(const std::filesystem::path& path, const char* folder,
                    std::filesystem::path& root) {
    std::error_code ec;
    const auto target = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec);
    root = std::filesystem::weakly_canonical(std::filesystem::absolute(folder, ec), ec);
    const std::filesystem::path rel = target.lexically_relative(root);
    return !ec && !rel.empty() && *rel.begin() != ".." && rel != ".";
}

// gaitlab.controller.load(path [, { sandbox = }]): runs a controller file once (in a sandbox
// unless told otherwise), caches the class it returns and watches the file for changes
int class_load(lua_State* L) {
    return protect(L, [&] {
        const std::string arg = check_string(L, 1);
        bool sandbox = true;
        if (!lua_isnoneornil(L, 2)) {
            Fields opts(L, 2, 2, {"sandbox"});
            sandbox = opts.boolean("sandbox", true);
            if (!sandbox && sandbox_folder(L)) {
                opts.fail("sandbox",
                          "a sandboxed controller file can only load files in a "
                          "sandbox");
            }
        }
        const std::filesystem::path path = script_path(L, arg);
        std::filesystem::path root;
        if (const char* folder = sandbox_folder(L); folder && !inside_sandbox(path, folder, root)) {
            // no access to files: not even whether one exists, or its first line in a message
            throw Error(
                fmt::format("cannot load controller '{}': outside the folder of the "
                            "sandboxed controller file ({}), where it may load files",
                            arg, root.string()));
        }
        // a replay has the code even where the file is gone (a path outside the run folder)
        if (!std::filesystem::exists(path) && !Reloader::of(L).has_override()) {
            throw Error(
                fmt::format("cannot load controller '{}': no file at {}", arg, path.string()));
        }
        try {
            push_file_class(L, path.string(), sandbox);
        } catch (const ReadError& e) {
            throw Error(fmt::format("cannot load controller '{}': {}", arg, e.what()));
        }
        return 1;
    });
}

// gaitlab.controller.templates(): the names of the embedded templates, sorted
int class_templates(lua_State* L) {
    return protect(L, [&] {
        lua_newtable(L);
        lua_Integer i = 0;
        for (const StdlibSource* t = controller_templates(); t->name; ++t) {
            const std::string_view file = t->name;
            lua_pushlstring(L, file.data(), file.size() - 4);
            lua_rawseti(L, -2, ++i);
        }
        return 1;
    });
}

// gaitlab.controller.template(name): the class an embedded template defines, ready to use
int class_template(lua_State* L) {
    return protect(L, [&] {
        const std::string name = check_string(L, 1);
        try {
            push_template_class(L, name);
        } catch (const SpecError& e) {
            throw ArgError(1, e.what());
        }
        return 1;
    });
}

// gaitlab.controller.write_template(name, path): copies a template into a new file to edit and
// load, creating missing folders; the path, or nil and a message if the file exists or cannot
// be written
int class_write_template(lua_State* L) {
    return protect(L, [&] {
        const StdlibSource* t = nullptr;
        try {
            t = &find_template(check_string(L, 1));
        } catch (const SpecError& e) {
            throw ArgError(1, e.what());
        }
        const ScriptPath target(L, check_string(L, 2));
        const std::string& file = target.path();
        const std::filesystem::path path(file);
        std::error_code ec;
        std::filesystem::path root;
        if (const char* folder = sandbox_folder(L); folder && !inside_sandbox(path, folder, root)) {
            // a sandboxed file writes only inside its own folder
            lua_pushnil(L);
            lua_pushstring(
                L, (target.shown(file) + ": outside the folder of the sandboxed controller file (" +
                    root.string() + "), where it may write")
                       .c_str());
            return 2;
        }
        if (std::filesystem::exists(path, ec)) {
            // a folder or a device there is no template of the user's
            const auto status = std::filesystem::status(path, ec);
            const char* what = std::filesystem::is_directory(status) ? "is a directory"
                               : !std::filesystem::is_regular_file(status)
                                   ? "not a regular file (a FIFO, device or socket)"
                                   : "file exists (templates never overwrite)";
            lua_pushnil(L);
            lua_pushstring(L, (target.shown(file) + ": " + what).c_str());
            return 2;
        }
        return file_written(L, target,
                            [&] { write_file_atomic(file, t->code, MissingFolders::create); });
    });
}

// gaitlab.controller.reload(): runs every loaded controller file again now; true, or false and
// the first error (the classes that failed keep their last good version)
int class_reload(lua_State* L) {
    return protect(L, [&] {
        const std::string error = Reloader::of(L).reload_all(L);
        lua_pushboolean(L, error.empty());
        if (error.empty()) return 1;
        lua_pushstring(L, error.c_str());
        return 2;
    });
}

}  // namespace

void push_controller(lua_State* L, std::shared_ptr<Controller> controller, bool attached) {
    ControllerHandle* h = push_canonical<ControllerHandle>(
        L, kControllerType, ControllerHandle{std::move(controller), attached});
    // the one handle of the controller: a caller that knows it drives a group says so
    h->attached = h->attached || attached;
}

void push_controller_api(lua_State* L, const char* sandbox_folder) {
    lua_newtable(L);
    const auto add = [&](const char* name, lua_CFunction fn) {
        if (sandbox_folder) {
            lua_pushstring(L, sandbox_folder);
            lua_pushcclosure(L, fn, 1);
        } else {
            lua_pushcfunction(L, fn);
        }
        lua_setfield(L, -2, name);
    };
    add("load", class_load);
    if (!sandbox_folder) add("reload", class_reload);  // a controller file reloads nothing
    add("templates", class_templates);
    add("template", class_template);
    add("write_template", class_write_template);
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, class_new);
    lua_setfield(L, -2, "__call");
    lua_setmetatable(L, -2);
}

void open_controller(lua_State* L) {
    const luaL_Reg methods[] = {{"params", controller_params},
                                {"values", controller_values},
                                {"set", controller_set},
                                {nullptr, nullptr}};
    const luaL_Reg meta[] = {{"__newindex", controller_newindex},
                             {"__tostring", controller_tostring},
                             {"__eq", controller_eq},
                             {nullptr, nullptr}};
    register_type_with_fields<ControllerHandle>(L, kControllerType, methods, controller_index,
                                                meta);

    const luaL_Reg class_meta[] = {{"__call", class_call},
                                   {"__index", class_index},
                                   {"__tostring", class_tostring},
                                   {nullptr, nullptr}};
    register_type<ClassPtr>(L, kControllerClassType, nullptr, class_meta);
    Reloader::install(L);

    // gaitlab.controllers.<name>{...}
    lua_newtable(L);
    for (const std::string& name : controllers::builtin_names()) {
        lua_pushstring(L, name.c_str());
        lua_pushcclosure(L, builtin_new, 1);
        lua_setfield(L, -2, name.c_str());
    }
    lua_setfield(L, -2, "controllers");

    // gaitlab.controller{...} and gaitlab.controller.load(path)
    push_controller_api(L, nullptr);
    lua_setfield(L, -2, "controller");
}

}  // namespace gaitlab::scripting
