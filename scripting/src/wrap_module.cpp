// gaitlab.module and gaitlab.modules: the module library and custom module types.
#include <cmath>

#include <fmt/format.h>

#include "fixed_order.h"
#include "lua_util.h"
#include "spec_fields.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

// registry key of the module library table, which gaitlab.modules shows read-only
constexpr const char* kLibraryKey = "gaitlab.modules";

ModuleDef& check_module(lua_State* L, int index) {
    return check_object<ModuleDef>(L, index, kModuleType);
}

bool is_builtin(const std::string& name) {
    for (const ModuleDef& m : builtin_modules()) {
        if (m.name == name) return true;
    }
    return false;
}

// the names in the library, sorted, for messages
std::vector<std::string> library_names(lua_State* L) {
    std::vector<std::string> names;
    lua_getfield(L, LUA_REGISTRYINDEX, kLibraryKey);
    lua_pushnil(L);
    while (lua_next(L, -2) != 0) {
        if (lua_type(L, -2) == LUA_TSTRING && luaL_testudata(L, -1, kModuleType)) {
            names.emplace_back(to_string(L, -2));
        }
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
    std::sort(names.begin(), names.end());
    return names;
}

void push_module(lua_State* L, ModuleDef m) {
    new_object<ModuleDef>(L, kModuleType, std::move(m));
}

// gaitlab.module{ name =, base =, shape =, ... }: a new module type, added to gaitlab.modules
int module_new(lua_State* L) {
    // called as gaitlab.module{...}: argument 1 is the gaitlab.module table itself
    return protect(L, [&] {
        Fields f(L, 2, 1,
                 {"name", "base", "shape", "length", "width", "height", "radius", "mass", "axis",
                  "range", "min", "max", "max_speed", "max_torque", "kp", "friction"});
        if (!f.has("name")) f.fail("name", "string expected, got nil");
        const std::string name = f.string("name", "");
        if (name.empty()) f.fail("name", "a module type needs a name");
        if (is_builtin(name)) {
            f.fail("name", "'" + name + "' is a built-in module type (choose another name)");
        }
        ModuleDef m = default_module_def();
        if (f.push("base") != LUA_TNIL) {
            try {
                m = to_module(L, -1);
            } catch (const Error& e) {
                lua_pop(L, 1);
                f.fail("base", e.what());
            }
        }
        lua_pop(L, 1);
        m.name = name;
        const std::string shape = f.string("shape", to_string(m.shape));
        if (shape == "box") {
            m.shape = Shape::box;
        } else if (shape == "cylinder") {
            m.shape = Shape::cylinder;
        } else {
            f.fail("shape", "'box' or 'cylinder' expected, got '" + shape + "'");
        }
        m.length = f.number("length", m.length);
        m.width = f.number("width", m.width);
        m.height = f.number("height", m.height);
        m.radius = f.number("radius", m.radius);
        m.mass = f.number("mass", m.mass);
        const std::string axis = f.string("axis", to_string(m.axis));
        if (axis == "bend") {
            m.axis = JointAxis::bend;
        } else if (axis == "twist") {
            m.axis = JointAxis::twist;
        } else {
            f.fail("axis", "'bend' or 'twist' expected, got '" + axis + "'");
        }
        const int range = f.push("range");
        if (range == LUA_TTABLE) {
            // two numbers and nothing else, as a vector's three (Fields::numbers)
            double r[2];
            f.numbers("range", {"min", "max"}, "range", r);
            m.min_angle = deg_to_rad(r[0]);
            m.max_angle = deg_to_rad(r[1]);
        } else {
            lua_pop(L, 1);
            if (range != LUA_TNIL) f.fail("range", "{min, max} in degrees expected");
        }
        // min and max (degrees), as a robot file's <module min= max=>
        if (f.has("range") && (f.has("min") || f.has("max"))) {
            f.fail(f.has("min") ? "min" : "max", "give range or min and max, not both");
        }
        if (f.has("min")) m.min_angle = deg_to_rad(f.number("min", 0));
        if (f.has("max")) m.max_angle = deg_to_rad(f.number("max", 0));
        m.servo.max_speed = servo_speed_field(f, "max_speed", m.servo.max_speed);
        m.servo.max_torque = f.number("max_torque", m.servo.max_torque);
        m.servo.kp = f.number("kp", m.servo.kp);
        m.friction = f.number("friction", m.friction);
        try {
            validate(m);
        } catch (const SpecError& e) {
            throw ArgError(1, e.what());
        }
        lua_getfield(L, LUA_REGISTRYINDEX, kLibraryKey);
        push_module(L, m);
        lua_pushvalue(L, -1);
        raw_setfield(L, -3, name.c_str());
        return 1;
    });
}

int module_index(lua_State* L) {
    return protect(L, [&] {
        const ModuleDef& m = check_module(L, 1);
        const std::string key = lua_type(L, 2) == LUA_TSTRING ? to_string(L, 2) : "";
        if (key == "name") {
            lua_pushstring(L, m.name.c_str());
        } else if (key == "shape") {
            lua_pushstring(L, to_string(m.shape));
        } else if (key == "axis") {
            lua_pushstring(L, to_string(m.axis));
        } else if (key == "range") {
            lua_createtable(L, 2, 0);
            lua_pushnumber(L, rad_to_deg(m.min_angle));
            lua_rawseti(L, -2, 1);
            lua_pushnumber(L, rad_to_deg(m.max_angle));
            lua_rawseti(L, -2, 2);
        } else if (key == "max_speed") {
            lua_pushnumber(L, rad_to_deg(m.servo.max_speed));
        } else if (key == "max_torque") {
            lua_pushnumber(L, m.servo.max_torque);
        } else if (key == "kp") {
            lua_pushnumber(L, m.servo.kp);
        } else {
            const std::pair<const char*, double> numbers[] = {
                {"length", m.length}, {"width", m.width}, {"height", m.height},
                {"radius", m.radius}, {"mass", m.mass},   {"friction", m.friction}};
            lua_pushnil(L);
            for (const auto& [name, value] : numbers) {
                if (key == name) {
                    lua_pop(L, 1);
                    lua_pushnumber(L, value);
                }
            }
        }
        return 1;
    });
}

int module_tostring(lua_State* L) {
    return protect(L, [&] {
        const ModuleDef& m = check_module(L, 1);
        lua_pushfstring(L, "gaitlab.Module '%s'", m.name.c_str());
        return 1;
    });
}

// gaitlab.modules[key] = value: the library changes only through gaitlab.module{...}, so the
// built-in types stay and every entry is a module type of that name
int library_newindex(lua_State* L) {
    return protect(L, [&]() -> int {
        const std::string key =
            lua_type(L, 2) == LUA_TSTRING ? " (cannot set '" + to_string(L, 2) + "')" : "";
        throw Error("gaitlab.modules is read-only" + key +
                    ": define a module type with gaitlab.module{ name = ..., ... }");
    });
}

// pairs(gaitlab.modules): the library's types, in the fixed order of the host's pairs (names in
// byte order), whichever pairs the script calls
int library_pairs(lua_State* L) {
    lua_pushcfunction(L, fixed_order_pairs);
    lua_getfield(L, LUA_REGISTRYINDEX, kLibraryKey);
    lua_call(L, 1, 3);
    return 3;
}

}  // namespace

ModuleDef to_module(lua_State* L, int index) {
    if (const void* p = luaL_testudata(L, index, kModuleType)) {
        return *static_cast<const ModuleDef*>(p);
    }
    if (lua_type(L, index) != LUA_TSTRING) {
        throw Error("module type name or gaitlab.Module expected, got " + type_name(L, index));
    }
    const std::string name = to_string(L, index);
    lua_getfield(L, LUA_REGISTRYINDEX, kLibraryKey);
    raw_getfield(L, -1, name);
    if (const void* p = luaL_testudata(L, -1, kModuleType)) {
        ModuleDef m = *static_cast<const ModuleDef*>(p);
        lua_pop(L, 2);
        return m;
    }
    lua_pop(L, 2);
    const std::vector<std::string> names = library_names(L);
    std::string list;
    for (const std::string& n : names)
        list += (list.empty() ? "" : ", ") + n;
    throw Error(fmt::format("unknown module type '{}'{} (module types: {})", name,
                            did_you_mean(name, names), list));
}

void open_module(lua_State* L) {
    const luaL_Reg meta[] = {
        {"__index", module_index}, {"__tostring", module_tostring}, {nullptr, nullptr}};
    register_type<ModuleDef>(L, kModuleType, nullptr, meta);

    // the library, built-in types first; gaitlab.module{...} adds to it
    lua_newtable(L);
    for (const ModuleDef& m : builtin_modules()) {
        push_module(L, m);
        lua_setfield(L, -2, m.name.c_str());
    }
    const int library = lua_gettop(L);
    lua_pushvalue(L, library);
    lua_setfield(L, LUA_REGISTRYINDEX, kLibraryKey);
    // gaitlab.modules: an empty table that reads the library and refuses writes (a table with
    // the types in it could not refuse `gaitlab.modules.cube = nil`); its metatable is
    // protected, so no script takes the guard off or gives the library metamethods
    lua_newtable(L);
    lua_createtable(L, 0, 4);
    lua_pushvalue(L, library);
    lua_setfield(L, -2, "__index");
    lua_pushcfunction(L, library_newindex);
    lua_setfield(L, -2, "__newindex");
    lua_pushcfunction(L, library_pairs);
    lua_setfield(L, -2, "__pairs");
    lua_pushliteral(L, "gaitlab.modules");
    lua_setfield(L, -2, "__metatable");
    lua_setmetatable(L, -2);
    lua_setfield(L, -3, "modules");
    lua_pop(L, 1);

    lua_newtable(L);
    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, module_new);
    lua_setfield(L, -2, "__call");
    lua_setmetatable(L, -2);
    lua_setfield(L, -2, "module");
}

}  // namespace gaitlab::scripting
