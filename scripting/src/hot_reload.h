// Hot reload of controller files: the files gaitlab.controller.load ran, checked for changes
// (modification time and size) at most every `interval` seconds of wall time from the steps of
// Lua controllers; a changed file is run again and its class replaces the old one in place.
// Also: the sandbox controller files run in, and the host's reporting hook.
#pragma once

#include <lua.hpp>

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "lua_controller.h"

namespace gaitlab::scripting {

/// Sends one message (no trailing newline) to the host's reporting hook (see
/// LuaHost::set_reporter); without one, writes "gaitlab: MESSAGE" to stderr.
void report(lua_State* L, const std::string& message);

/// Pushes a fresh environment for a sandboxed controller file: the basic functions without
/// file, module or debug access, copies of math, string, table and utf8, and gaitlab.controller.
void push_sandbox(lua_State* L);

/// Loads the Lua file `chunk` (text only), in a sandbox if asked, and runs it; leaves its one
/// result on the stack. Throws ScriptError (syntax or runtime).
void run_controller_file(lua_State* L, const std::string& chunk, bool sandbox);

/// Runs controller source text (an embedded template) in a sandbox as chunk "=name"; leaves its
/// one result on the stack. Throws ScriptError.
void run_controller_source(lua_State* L, std::string_view code, const std::string& name);

struct StdlibSource;

/// Pushes the class of the controller file at `path` (made absolute and normal): the cached
/// class if the file was loaded before, else runs the file (in a sandbox if asked), checks that
/// it returns gaitlab.controller{...}, caches the class, records its origin and watches the
/// file for hot reload. Throws ScriptError or Error naming the file.
void push_file_class(lua_State* L, const std::string& path, bool sandbox);

/// The embedded template called `name` (without ".lua"); throws SpecError naming the others.
const StdlibSource& find_template(std::string_view name);

/// Pushes a new class made from the embedded template `name`; throws SpecError or ScriptError.
void push_template_class(lua_State* L, std::string_view name);

class Reloader {
  public:
    /// The reloader of the Lua state (created by open_controller).
    static Reloader& of(lua_State* L);
    /// Creates it and keeps it in the registry.
    static void install(lua_State* L);

    /// Starts watching the file a class was loaded from.
    void watch(const std::shared_ptr<LuaControllerClass>& cls, const std::string& chunk,
               bool sandbox);
    /// Called from every Lua controller step: cheap unless `interval` has passed since the last
    /// check, then reloads the files that changed (failures are reported, never thrown).
    void poll(lua_State* L) {
        if (files_.empty()) return;
        const auto now = std::chrono::steady_clock::now();
        if (now < next_check_) return;
        next_check_ = now + interval_;
        check(L, false);
    }
    /// Reloads every watched file, changed or not; returns the first error ("" if none).
    std::string reload_all(lua_State* L) { return check(L, true); }

    /// Wall time between two checks, s.
    void set_interval(double seconds) {
        interval_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(seconds));
    }

  private:
    struct Stamp {
        bool exists = false;
        std::int64_t mtime = 0;
        std::uintmax_t size = 0;
        bool operator==(const Stamp& o) const {
            return exists == o.exists && mtime == o.mtime && size == o.size;
        }
    };
    struct File {
        std::weak_ptr<LuaControllerClass> cls;
        std::string chunk;
        bool sandbox = true;
        Stamp stamp;
    };
    static Stamp stamp_of(const std::string& path);
    std::string check(lua_State* L, bool force);
    // runs the file again and swaps the class in place; returns the error ("" on success)
    static std::string reload(lua_State* L, File& f, LuaControllerClass& cls);

    std::vector<File> files_;
    std::chrono::steady_clock::duration interval_ = std::chrono::milliseconds(200);
    std::chrono::steady_clock::time_point next_check_{};
};

}  // namespace gaitlab::scripting
