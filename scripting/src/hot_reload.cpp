#include "hot_reload.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string_view>

#include <fmt/format.h>

#include "gaitlab/files.h"
#include "gaitlab/terminal.h"
#include "guard.h"
#include "lua_util.h"
#include "recording.h"
#include "sandbox.h"
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
    log_to_recordings(L, "gaitlab: " + message);
    if (lua_getfield(L, LUA_REGISTRYINDEX, kReporterKey) == LUA_TUSERDATA) {
        auto* fn = static_cast<std::function<void(const std::string&)>*>(lua_touserdata(L, -1));
        lua_pop(L, 1);
        (*fn)(message);
        return;
    }
    lua_pop(L, 1);
    report_line(message);
}

void run_controller_source(lua_State* L, const std::string& source, const std::string& chunk,
                           bool sandbox) {
    load_source(L, source, chunk);
    if (sandbox) {
        push_sandbox(L, chunk);
        if (!lua_setupvalue(L, -2, 1)) lua_pop(L, 1);  // the chunk's only upvalue is _ENV
    }
    const std::string what = "controller file " + chunk;
    const Budget limit(L, kLoadInstructionBudget, what, " while it loaded");
    protected_call(L, 0, 1);
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
    Reloader::of(L).load(L, std::filesystem::path(path).lexically_normal().string(), sandbox);
    auto& cls = *static_cast<std::shared_ptr<LuaControllerClass>*>(lua_touserdata(L, -1));
    cls->origin_kind = ControllerRef::Kind::file;
    cls->origin = key;
    lua_pushvalue(L, -1);
    lua_setfield(L, -3, key.c_str());
    lua_remove(L, -2);
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
    const std::string chunk = std::string("template/") + t.name;
    run_controller_source(L, t.code, chunk, true);
    auto* p = static_cast<std::shared_ptr<LuaControllerClass>*>(
        luaL_testudata(L, -1, kControllerClassType));
    if (!p) {
        const std::string got = type_name(L, -1);
        lua_pop(L, 1);
        throw Error(fmt::format(
            "{}: a controller file must return gaitlab.controller{{...}}, got {}", chunk, got));
    }
    auto& cls = *p;
    cls->origin_kind = ControllerRef::Kind::template_;
    cls->origin = std::string(name);
}

Reloader& Reloader::of(lua_State* L) {
    lua_getfield(L, LUA_REGISTRYINDEX, kReloaderKey);
    auto* r = static_cast<Reloader*>(luaL_testudata(L, -1, kReloaderType));
    lua_pop(L, 1);
    if (!r) throw Error("the controller files' reloader is gone (the Lua state is closing)");
    return *r;
}

void Reloader::install(lua_State* L) {
    register_type<Reloader>(L, kReloaderType, nullptr);
    new_object<Reloader>(L, kReloaderType, Reloader{});
    lua_setfield(L, LUA_REGISTRYINDEX, kReloaderKey);
}

std::string Reloader::source_of(size_t index, std::uint64_t version,
                                const std::string& chunk) const {
    if (override_) {
        if (auto o = override_(index, version)) return *o;
    }
    return read_file(chunk);  // bounded, and never a FIFO or a device
}

void Reloader::load(lua_State* L, const std::string& chunk, bool sandbox) {
    const size_t index = files_.size();
    const std::string source = source_of(index, 0, chunk);
    run_controller_source(L, source, chunk, sandbox);
    if (!luaL_testudata(L, -1, kControllerClassType)) {
        const std::string t = type_name(L, -1);
        lua_pop(L, 1);
        throw Error(fmt::format(
            "{}: a controller file must return gaitlab.controller{{...}}, got {}", chunk, t));
    }
    const auto& cls = *static_cast<std::shared_ptr<LuaControllerClass>*>(lua_touserdata(L, -1));
    files_.push_back(File{cls, chunk, sandbox, stamp_of(chunk), {source}});
    if (next_check_ == std::chrono::steady_clock::time_point{}) {
        next_check_ = std::chrono::steady_clock::now() + interval_;
    }
    if (observer_) observer_(L, Change{index, chunk, source, 0, Origin::script, *cls});
}

std::vector<Reloader::FileRecord> Reloader::history() const {
    std::vector<FileRecord> out;
    for (const File& f : files_)
        out.push_back(FileRecord{f.chunk, f.versions});
    return out;
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

std::string Reloader::check(lua_State* L, bool force, Origin origin) {
    std::string first;
    for (size_t i = 0; i < files_.size(); ++i) {
        if (!files_[i].cls.lock()) continue;
        const Stamp now = stamp_of(files_[i].chunk);
        if (!force && now == files_[i].stamp) continue;
        files_[i].stamp = now;  // a broken version is reported once, not at every check
        std::string error = reload_one(L, i, origin);
        if (!error.empty()) {
            report(L, "reload failed: " + error);
            if (first.empty()) first = error;
        }
    }
    return first;
}

std::string Reloader::reload_file(lua_State* L, size_t index, Origin origin) {
    if (index >= files_.size()) return fmt::format("no controller file number {}", index + 1);
    return reload_one(L, index, origin);
}

std::string Reloader::reload_one(lua_State* L, size_t i, Origin origin) {
    std::shared_ptr<LuaControllerClass> cls = files_[i].cls.lock();
    if (!cls) return "";
    std::string error;
    std::string source;
    try {
        source = source_of(i, cls->version + 1, files_[i].chunk);
    } catch (const ReadError& e) {
        error = fmt::format("{}: cannot read the file ({}); '{}' keeps its last good version",
                            files_[i].chunk, e.reason(), cls->def.name);
    }
    if (error.empty()) {
        // reload() may load other files: copy what it needs, files_ may grow
        const File f = files_[i];
        error = reload(L, f, source, *cls);
    }
    cls->reload_error = error;
    if (error.empty()) {
        files_[i].versions.push_back(source);
        if (observer_) {
            observer_(L, Change{i, files_[i].chunk, files_[i].versions.back(), cls->version, origin,
                                *cls});
        }
    }
    return error;
}

std::string Reloader::reload(lua_State* L, const File& f, const std::string& source,
                             LuaControllerClass& cls) {
    const int top = lua_gettop(L);
    std::shared_ptr<LuaControllerClass> fresh;
    try {
        run_controller_source(L, source, f.chunk, f.sandbox);
        if (!luaL_testudata(L, -1, kControllerClassType)) {
            const std::string t = type_name(L, -1);
            lua_settop(L, top);
            return fmt::format(
                "{}: a controller file must return gaitlab.controller{{...}}, got {}", f.chunk, t);
        }
        fresh = *static_cast<std::shared_ptr<LuaControllerClass>*>(lua_touserdata(L, -1));
        lua_settop(L, top);
        // the old code takes its snapshots before it goes. By index: a snapshot is Lua code,
        // which may make instances of the class or let the collector destroy some
        for (size_t k = 0; k < cls.instances.size(); ++k)
            cls.instances[k]->take_snapshot();
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
