#include "hot_reload.h"

#include <cstdio>
#include <filesystem>
#include <functional>
#include <string_view>

#include <fmt/format.h>

#include "lua_util.h"
#include "stdlib.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

constexpr const char* kReloaderKey = "gaitlab.reloader";
constexpr const char* kReloaderType = "gaitlab.Reloader";
// registry table: canonical path of a controller file -> its class
constexpr const char* kFileClassesKey = "gaitlab.controller_files";

}  // namespace

void report(lua_State* L, const std::string& message) {
    if (lua_getfield(L, LUA_REGISTRYINDEX, kReporterKey) == LUA_TUSERDATA) {
        auto* fn = static_cast<std::function<void(const std::string&)>*>(lua_touserdata(L, -1));
        lua_pop(L, 1);
        (*fn)(message);
        return;
    }
    lua_pop(L, 1);
    std::fprintf(stderr, "gaitlab: %s\n", message.c_str());
}

void push_sandbox(lua_State* L) {
    lua_newtable(L);
    for (const char* name :
         {"assert", "error", "getmetatable", "ipairs", "next", "pairs", "pcall", "print",
          "rawequal", "rawget", "rawlen", "rawset", "select", "setmetatable", "tonumber",
          "tostring", "type", "xpcall", "_VERSION"}) {
        lua_getglobal(L, name);
        lua_setfield(L, -2, name);
    }
    // copies, so a controller file cannot change the libraries everyone else uses
    for (const char* lib : {"math", "string", "table", "utf8"}) {
        lua_newtable(L);
        if (lua_getglobal(L, lib) == LUA_TTABLE) {
            lua_pushnil(L);
            while (lua_next(L, -2) != 0) {
                lua_pushvalue(L, -2);
                lua_insert(L, -2);
                lua_rawset(L, -5);
            }
        }
        lua_pop(L, 1);
        lua_setfield(L, -2, lib);
    }
    lua_createtable(L, 0, 1);
    if (lua_getglobal(L, "gaitlab") == LUA_TTABLE)
        lua_getfield(L, -1, "controller");
    else
        lua_pushnil(L);
    lua_setfield(L, -3, "controller");
    lua_pop(L, 1);
    lua_setfield(L, -2, "gaitlab");
    lua_pushvalue(L, -1);
    lua_setfield(L, -2, "_G");
}

namespace {

// runs the chunk on top of the stack (in a sandbox if asked); leaves its one result
void run_loaded_chunk(lua_State* L, bool sandbox) {
    if (sandbox) {
        push_sandbox(L);
        if (!lua_setupvalue(L, -2, 1)) lua_pop(L, 1);  // the chunk's only upvalue is _ENV
    }
    protected_call(L, 0, 1);
}

}  // namespace

void run_controller_file(lua_State* L, const std::string& chunk, bool sandbox) {
    if (luaL_loadfilex(L, chunk.c_str(), "t") != LUA_OK) {
        std::string msg = lua_tostring(L, -1);
        lua_pop(L, 1);
        throw ScriptError(msg, chunk, 0, "");
    }
    run_loaded_chunk(L, sandbox);
}

void run_controller_source(lua_State* L, std::string_view code, const std::string& name) {
    const std::string chunk = "=" + name;  // not a file: relative paths ignore it
    if (luaL_loadbufferx(L, code.data(), code.size(), chunk.c_str(), "t") != LUA_OK) {
        std::string msg = lua_tostring(L, -1);
        lua_pop(L, 1);
        throw ScriptError(msg, name, 0, "");
    }
    run_loaded_chunk(L, true);
}

void push_file_class(lua_State* L, const std::string& path, bool sandbox) {
    std::error_code ec;
    const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(absolute, ec);
    const std::string key = (ec ? absolute : canonical).string();
    if (lua_getfield(L, LUA_REGISTRYINDEX, kFileClassesKey) != LUA_TTABLE) {
        lua_pop(L, 1);
        lua_newtable(L);
        lua_pushvalue(L, -1);
        lua_setfield(L, LUA_REGISTRYINDEX, kFileClassesKey);
    }
    if (lua_getfield(L, -1, key.c_str()) != LUA_TNIL) {
        lua_remove(L, -2);
        return;
    }
    lua_pop(L, 1);
    const std::string chunk = std::filesystem::path(path).lexically_normal().string();
    run_controller_file(L, chunk, sandbox);
    if (!luaL_testudata(L, -1, kControllerClassType)) {
        const std::string t = type_name(L, -1);
        lua_pop(L, 2);
        throw Error(fmt::format(
            "{}: a controller file must return gaitlab.controller{{...}}, got {}", chunk, t));
    }
    auto& cls = *static_cast<std::shared_ptr<LuaControllerClass>*>(lua_touserdata(L, -1));
    cls->origin_kind = ControllerRef::Kind::file;
    cls->origin = key;
    lua_pushvalue(L, -1);
    lua_setfield(L, -3, key.c_str());
    lua_remove(L, -2);
    Reloader::of(L).watch(cls, chunk, sandbox);
}

const StdlibSource& find_template(std::string_view name) {
    std::vector<std::string> names;
    for (const StdlibSource* t = controller_templates(); t->name; ++t) {
        const std::string_view file = t->name;
        const std::string_view stem = file.substr(0, file.size() - 4);  // without ".lua"
        if (stem == name) return *t;
        names.emplace_back(stem);
    }
    throw SpecError(fmt::format("unknown template '{}'{} (templates: {})", name,
                                did_you_mean(name, names), fmt::join(names, ", ")));
}

void push_template_class(lua_State* L, std::string_view name) {
    const StdlibSource& t = find_template(name);
    run_controller_source(L, t.code, std::string("template/") + t.name);
    auto& cls = *static_cast<std::shared_ptr<LuaControllerClass>*>(
        luaL_checkudata(L, -1, kControllerClassType));
    cls->origin_kind = ControllerRef::Kind::template_;
    cls->origin = std::string(name);
}

Reloader& Reloader::of(lua_State* L) {
    lua_getfield(L, LUA_REGISTRYINDEX, kReloaderKey);
    auto* r = static_cast<Reloader*>(lua_touserdata(L, -1));
    lua_pop(L, 1);
    return *r;
}

void Reloader::install(lua_State* L) {
    register_type<Reloader>(L, kReloaderType, nullptr);
    new_object<Reloader>(L, kReloaderType, Reloader{});
    lua_setfield(L, LUA_REGISTRYINDEX, kReloaderKey);
}

void Reloader::watch(const std::shared_ptr<LuaControllerClass>& cls, const std::string& chunk,
                     bool sandbox) {
    files_.push_back(File{cls, chunk, sandbox, stamp_of(chunk)});
    if (next_check_ == std::chrono::steady_clock::time_point{}) {
        next_check_ = std::chrono::steady_clock::now() + interval_;
    }
}

Reloader::Stamp Reloader::stamp_of(const std::string& path) {
    std::error_code ec;
    Stamp s;
    const auto t = std::filesystem::last_write_time(path, ec);
    if (ec) return s;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) return s;
    s.exists = true;
    s.mtime = static_cast<std::int64_t>(t.time_since_epoch().count());
    s.size = size;
    return s;
}

std::string Reloader::check(lua_State* L, bool force) {
    std::string first;
    for (size_t i = 0; i < files_.size(); ++i) {
        std::shared_ptr<LuaControllerClass> cls = files_[i].cls.lock();
        if (!cls) continue;
        const Stamp now = stamp_of(files_[i].chunk);
        if (!force && now == files_[i].stamp) continue;
        files_[i].stamp = now;  // a broken version is reported once, not at every check
        std::string error;
        if (!now.exists) {
            error = fmt::format(
                "{}: cannot read the file (deleted?); '{}' keeps its last good "
                "version",
                files_[i].chunk, cls->def.name);
        } else {
            // reload() may load other files: copy what it needs, files_ may grow
            File f = files_[i];
            error = reload(L, f, *cls);
        }
        cls->reload_error = error;
        if (!error.empty()) {
            report(L, "reload failed: " + error);
            if (first.empty()) first = error;
        }
    }
    return first;
}

std::string Reloader::reload(lua_State* L, File& f, LuaControllerClass& cls) {
    const int top = lua_gettop(L);
    std::shared_ptr<LuaControllerClass> fresh;
    try {
        run_controller_file(L, f.chunk, f.sandbox);
        if (!luaL_testudata(L, -1, kControllerClassType)) {
            const std::string t = type_name(L, -1);
            lua_settop(L, top);
            return fmt::format(
                "{}: a controller file must return gaitlab.controller{{...}}, got {}", f.chunk, t);
        }
        fresh = *static_cast<std::shared_ptr<LuaControllerClass>*>(lua_touserdata(L, -1));
        lua_settop(L, top);
        // the old code takes its snapshots before it goes
        for (LuaController* c : cls.instances)
            c->take_snapshot();
    } catch (const ScriptError& e) {
        lua_settop(L, top);
        for (LuaController* c : cls.instances)
            c->drop_snapshot();
        return e.what();
    }
    auto take = [](int& ref) {
        const int r = ref;
        ref = LUA_NOREF;
        return r;
    };
    luaL_unref(L, LUA_REGISTRYINDEX, cls.step_ref);
    luaL_unref(L, LUA_REGISTRYINDEX, cls.snapshot_ref);
    luaL_unref(L, LUA_REGISTRYINDEX, cls.on_reload_ref);
    cls.def = fresh->def;
    cls.step_ref = take(fresh->step_ref);
    cls.snapshot_ref = take(fresh->snapshot_ref);
    cls.on_reload_ref = take(fresh->on_reload_ref);
    cls.budget = fresh->budget;
    cls.line = fresh->line;
    ++cls.version;
    // the fix a student saved revives a failed controller: it runs the new version at the next
    // control tick, from the state it had when it failed
    for (LuaController* c : cls.instances) {
        if (c->failed()) c->set_failed(false);
    }
    return "";
}

}  // namespace gaitlab::scripting
