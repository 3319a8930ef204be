// Hot reload of controller files: the files gaitlab.controller.load ran, checked for changes
// (modification time and size) at most every `interval` seconds of wall time, between the ticks
// of the simulations (at control ticks); a changed file is run again and its class replaces the
// old one in place. The reloader keeps the source of every version it ran, in load order, so a
// recording can copy them and a replay can run them again (controller files run in the sandbox
// of sandbox.h). Also: the host's reporting hook.
#pragma once

#include <lua.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gaitlab/event.h"
#include "lua_controller.h"

namespace gaitlab::scripting {

/// Sends one message (no trailing newline) to the host's reporting hook (see
/// LuaHost::set_reporter); without one, writes "gaitlab: MESSAGE" to stderr.
void report(lua_State* L, const std::string& message);

/// Runs `source` as the Lua file `chunk` (text only), in a sandbox if asked; leaves its one
/// result on the stack. Throws ScriptError (syntax or runtime).
void run_controller_source(lua_State* L, const std::string& source, const std::string& chunk,
                           bool sandbox);

struct StdlibSource;

/// Pushes the class of the controller file at `path` (made absolute and normal): the cached
/// class if the file was loaded before, else loads it through the reloader (which watches it for
/// hot reload), caches it and records its origin (for actuation files). Throws ScriptError or
/// Error naming the file.
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

    /// What happened to a controller file: loaded (version 0) or reloaded (version >= 1).
    struct Change {
        size_t index;               ///< load order, from 0
        const std::string& chunk;   ///< its path
        const std::string& source;  ///< the code that ran
        std::uint64_t version;      ///< the class version it became
        Origin origin;              ///< script (load, reload()) or file (changed on disk)
        const LuaControllerClass& cls;
    };
    /// Called after every successful load and reload (one observer: the recordings).
    void set_observer(std::function<void(lua_State*, const Change&)> fn) {
        observer_ = std::move(fn);
    }
    /// Replay: the code to run for file `index` at `version` instead of the file's content, or
    /// nullopt to read the file.
    using SourceOverride =
        std::function<std::optional<std::string>(size_t index, std::uint64_t version)>;
    void set_source_override(SourceOverride fn) { override_ = std::move(fn); }
    /// Whether the next file to load has overriding code (then it need not exist).
    bool has_override() const { return override_ && override_(files_.size(), 0).has_value(); }
    /// Replay: no checks of the files for changes (recorded reloads are applied instead).
    void set_polling(bool on) { polling_ = on; }

    /// Runs the controller file `chunk` (or its override), checks that it returns a class,
    /// starts watching it and leaves the class on the stack; throws ScriptError or Error.
    void load(lua_State* L, const std::string& chunk, bool sandbox);
    /// Called between ticks: cheap unless `interval` has passed since the last check, then
    /// reloads the files that changed (failures are reported, never thrown).
    void poll(lua_State* L) {
        if (files_.empty() || !polling_) return;
        const auto now = std::chrono::steady_clock::now();
        if (now < next_check_) return;
        next_check_ = now + interval_;
        check(L, false, Origin::file);
    }
    /// Whether poll has files to check.
    bool watching() const { return !files_.empty() && polling_; }
    /// Reloads every watched file, changed or not; returns the first error ("" if none).
    std::string reload_all(lua_State* L) { return check(L, true, Origin::script); }
    /// Reloads file `index` now (a recorded reload being replayed); returns the error, "" if
    /// none.
    std::string reload_file(lua_State* L, size_t index, Origin origin);

    /// The files loaded so far, in load order, with the source of each version.
    struct FileRecord {
        std::string chunk;
        std::vector<std::string> versions;  ///< source of version 0, 1, ...
    };
    std::vector<FileRecord> history() const;

    /// Wall time between two checks, s.
    double interval() const { return std::chrono::duration<double>(interval_).count(); }
    /// A shorter interval takes effect at once: the next check is due no later than `seconds`
    /// from now (not at the end of the longer interval already begun).
    void set_interval(double seconds) {
        interval_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(seconds));
        if (next_check_ != std::chrono::steady_clock::time_point{})
            next_check_ = std::min(next_check_, std::chrono::steady_clock::now() + interval_);
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
        std::vector<std::string> versions;  // the source of each version that ran
    };
    static Stamp stamp_of(const std::string& path);
    std::string check(lua_State* L, bool force, Origin origin);
    std::string reload_one(lua_State* L, size_t index, Origin origin);
    // the code of file `index` at `version`: the override, or the file; throws Error
    std::string source_of(size_t index, std::uint64_t version, const std::string& chunk) const;
    // runs the file again and swaps the class in place; returns the error ("" on success)
    static std::string reload(lua_State* L, const File& f, const std::string& source,
                              LuaControllerClass& cls);

    std::vector<File> files_;
    std::function<void(lua_State*, const Change&)> observer_;
    SourceOverride override_;
    bool polling_ = true;
    std::chrono::steady_clock::duration interval_ = std::chrono::milliseconds(200);
    std::chrono::steady_clock::time_point next_check_{};
};

}  // namespace gaitlab::scripting
