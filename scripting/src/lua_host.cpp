#include "gaitlab/scripting/lua_host.h"

#include <lua.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "config_files.h"
#include "fixed_order.h"
#include "gaitlab/files.h"
#include "gaitlab/terminal.h"
#include "guard.h"
#include "hot_reload.h"
#include "lua_util.h"
#include "playback.h"
#include "recording.h"
#include "stdlib.h"

extern "C" int luaopen_gaitlab(lua_State* L);

namespace gaitlab::scripting {

namespace {

// package.searchers' second entry in a host: `require "name"` finds name.lua (a dotted name in
// folders: "gait.util" is gait/util.lua) in the folder of the Lua file that requires it, before
// package.path, so a script's own modules travel with it (`gaitlab run` from any folder finds
// them). The file is read as the script's other inputs: a recorded run keeps a copy in its
// config/, and its replay loads that copy. Lua's own searchers come after it.
int script_folder_searcher(lua_State* L) {
    return protect(L, [&] {
        std::string relative = check_string(L, 1);
        // all of the name: "mod\0evil" is no module (Lua's require hands its searchers the
        // name up to a zero byte, as it always has; this is for a script calling the searcher)
        refuse_zero_byte(relative);
        // "a.b" is a/b.lua; a name with an empty part ("..x", "a..b", ".a") would make a path
        // from the file system's root or with "//": no module of this folder has such a name
        if (relative.empty() || relative.front() == '.' || relative.back() == '.' ||
            relative.find("..") != std::string::npos) {
            lua_pushfstring(L,
                            "no module '%s' beside the requiring script (names are NAME or "
                            "FOLDER.NAME)",
                            relative.c_str());
            return 1;
        }
        std::replace(relative.begin(), relative.end(), '.', '/');
        relative += ".lua";
        // the file beside the script, or in a replay the run folder's copy of it; noted as an
        // input when it can be read
        const std::string read = input_path(L, relative);
        std::error_code ec;
        if (!std::filesystem::is_regular_file(read, ec)) {
            // something else of that name is there: say what, not that nothing is
            const auto status = std::filesystem::status(read, ec);
            const char* what = !std::filesystem::exists(status) ? nullptr
                               : std::filesystem::is_directory(status)
                                   ? "is a directory"
                                   : "not a regular file (a FIFO, device or socket)";
            if (what) {
                lua_pushfstring(L, "'%s' beside the requiring script %s", read.c_str(), what);
            } else {
                lua_pushfstring(L, "no file '%s' (beside the requiring script)", read.c_str());
            }
            return 1;
        }
        const std::string text = read_file(read);
        const std::string chunk = "@" + read;
        if (luaL_loadbufferx(L, text.data(), text.size(), chunk.c_str(), "t") != LUA_OK)
            throw Error(located_load_error(to_string(L, -1), read));  // at its file and line
        lua_pushstring(L, read.c_str());
        return 2;
    });
}

// what a new host's state starts with: Lua's libraries with `pairs` and `table.sort` in a fixed
// order (fixed_order.h), the searcher above, and gaitlab as the global `gaitlab`
int open_host_libraries(lua_State* L) {
    luaL_openlibs(L);
    open_fixed_order(L);
    lua_getglobal(L, "package");
    lua_getfield(L, -1, "searchers");
    for (lua_Integer i = static_cast<lua_Integer>(luaL_len(L, -1)); i >= 2; --i) {
        lua_rawgeti(L, -1, i);
        lua_rawseti(L, -2, i + 1);
    }
    lua_pushcfunction(L, script_folder_searcher);
    lua_rawseti(L, -2, 2);
    lua_pop(L, 2);
    luaL_requiref(L, "gaitlab", luaopen_gaitlab, 1);
    return 0;
}

// math.randomseed(seed as upvalue-less argument 1), through the math library of the state
int seed_random(lua_State* L) {
    lua_getglobal(L, "math");
    lua_getfield(L, -1, "randomseed");
    lua_pushvalue(L, 1);
    lua_call(L, 1, 0);
    return 0;
}

// `path` made absolute and normal (as given if that fails): what a simulation file's messages
// and its parts' paths start from
std::string absolute_path(const std::string& path) {
    std::error_code ec;
    const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
    return ec ? path : absolute.lexically_normal().string();
}

// pushes gaitlab.simulation[name] (a function of stdlib/simulation.lua)
void push_simulation_function(lua_State* L, const char* name) {
    lua_getglobal(L, "gaitlab");
    lua_getfield(L, -1, "simulation");
    lua_getfield(L, -1, name);
}

// gaitlab.simulation.run_file(argument 1)
int run_simulation_file_of(lua_State* L) {
    push_simulation_function(L, "run_file");
    lua_pushvalue(L, 1);
    lua_call(L, 1, 0);
    return 0;
}

// gaitlab.simulation.check_file(argument 1, { seconds = 2, cycle = 3, settle = 4 }), a zero
// leaving the key out; returns how many warnings it gave
int check_simulation_file_of(lua_State* L) {
    push_simulation_function(L, "check_file");
    lua_pushvalue(L, 1);
    lua_createtable(L, 0, 3);
    const char* keys[] = {"seconds", "cycle", "settle"};
    for (int k = 0; k < 3; ++k) {
        if (lua_tonumber(L, 2 + k) == 0) continue;
        lua_pushvalue(L, 2 + k);
        lua_setfield(L, -2, keys[k]);
    }
    lua_call(L, 2, 1);
    lua_getfield(L, -1, "warnings");
    lua_pushinteger(L, static_cast<lua_Integer>(luaL_len(L, -1)));
    return 1;
}

// message handler: turns the error into a table {message, file, line, traceback} while the
// stack of the failed call is still there
int message_handler(lua_State* L) {
    // the message as a Lua string, all of it (a zero byte in it included): at `msg`
    if (lua_isstring(L, 1)) {
        lua_tostring(L, 1);  // a number as its text, in place (a string from here on)
        lua_pushvalue(L, 1);
    } else if (!(luaL_callmeta(L, 1, "__tostring") && lua_type(L, -1) == LUA_TSTRING)) {
        lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
    }
    const int msg = lua_gettop(L);
    lua_createtable(L, 0, 4);
    lua_pushvalue(L, msg);
    lua_setfield(L, -2, "message");
    luaL_traceback(L, L, nullptr, 1);
    lua_setfield(L, -2, "traceback");
    // an error that crossed C++ on its way here (a Lua controller failing inside sim:run) keeps
    // the place it happened, which push_script_error left in the registry
    if (lua_getfield(L, LUA_REGISTRYINDEX, kErrorOriginKey) == LUA_TTABLE) {
        lua_pushnil(L);
        lua_setfield(L, LUA_REGISTRYINDEX, kErrorOriginKey);
        lua_getfield(L, -1, "message");
        lua_getfield(L, -2, "file");
        const bool known =
            lua_type(L, 1) == LUA_TSTRING && lua_rawequal(L, -2, 1) && lua_rawlen(L, -1) > 0;
        lua_pop(L, 2);
        if (known) {
            lua_getfield(L, -1, "file");
            lua_setfield(L, -3, "file");
            lua_getfield(L, -1, "line");
            lua_setfield(L, -3, "line");
            // the traceback taken where it happened already goes down to this call
            if (lua_getfield(L, -1, "traceback") == LUA_TSTRING && lua_rawlen(L, -1) > 0) {
                lua_setfield(L, -3, "traceback");
            } else {
                lua_pop(L, 1);
            }
            lua_pop(L, 1);
            return 1;
        }
    }
    lua_pop(L, 1);
    // the innermost Lua function on the stack is where the error happened
    lua_Debug ar;
    for (int level = 1; lua_getstack(L, level, &ar); ++level) {
        lua_getinfo(L, "Sl", &ar);
        if (ar.currentline > 0) {
            lua_pushstring(L, ar.source[0] == '@' ? ar.source + 1 : ar.short_src);
            lua_setfield(L, -2, "file");
            lua_pushinteger(L, ar.currentline);
            lua_setfield(L, -2, "line");
            // an error value that is not a string carries no position: give it one
            if (lua_type(L, 1) != LUA_TSTRING) {
                lua_pushfstring(L, "%s:%d: ", ar.short_src, ar.currentline);
                lua_pushvalue(L, msg);
                lua_concat(L, 2);
                lua_setfield(L, -2, "message");
            }
            break;
        }
    }
    return 1;
}

std::string field_string(lua_State* L, const char* key) {
    lua_getfield(L, -1, key);
    std::string s = lua_isstring(L, -1) ? to_string(L, -1) : "";
    lua_pop(L, 1);
    return s;
}

}  // namespace

void protected_call(lua_State* L, int nargs, int nresults) {
    const int base = lua_gettop(L) - nargs;
    lua_pushcfunction(L, message_handler);
    lua_insert(L, base);
    const int status = lua_pcall(L, nargs, nresults, base);
    if (status == LUA_OK) {
        lua_remove(L, base);
        return;
    }
    std::string message, file, traceback;
    int line = 0;
    if (lua_istable(L, -1)) {
        message = field_string(L, "message");
        file = field_string(L, "file");
        traceback = field_string(L, "traceback");
        lua_getfield(L, -1, "line");
        line = static_cast<int>(lua_tointeger(L, -1));
        lua_pop(L, 1);
    } else {
        message = lua_isstring(L, -1) ? to_string(L, -1) : "error in error handling";
    }
    lua_settop(L, base - 1);
    // an interrupt says so, even where the state was too full for its message to be made
    if (status == LUA_ERRMEM || status == LUA_ERRERR) {
        const Guard* g = Guard::find(L);
        if (g && g->interrupted() != 0) message = g->interrupt_message();
    }
    throw ScriptError(message, file, line, traceback);
}

struct LuaHost::Memory : MemoryLimit {};

LuaHost::LuaHost(std::size_t memory_limit)
    : memory_(std::make_unique<Memory>(Memory{{memory_limit}})),
      L_(lua_newstate(MemoryLimit::alloc, memory_.get())) {
    if (!L_) throw Error("cannot create a Lua state: out of memory");
    // only a failure outside any protected call (a broken build) ends here, never a script
    lua_atpanic(L_, [](lua_State* S) -> int {
        const char* msg = lua_tostring(S, -1);
        print_message(stderr, "gaitlab: unprotected Lua error: %s\n", msg ? msg : "?");
        return 0;
    });
    try {
        lua_pushcfunction(L_, open_host_libraries);
        protected_call(L_, 0, 0);
    } catch (...) {
        lua_close(L_);  // the destructor will not run
        throw;
    }
    guard_ = &Guard::of(L_);
    // Lua 5.4 seeds math.random from the clock: seed 0 unless told otherwise, so every run is
    // reproducible and its recorded seed is true
    seed(0);
}

LuaHost::~LuaHost() {
    lua_close(L_);
}

void LuaHost::interrupt(int signal) {
    guard_->interrupt(L_, signal);
}

int LuaHost::interrupted() const {
    return guard_->interrupted();
}

void LuaHost::clear_interrupt() {
    guard_->clear_interrupt(L_);
}

void LuaHost::seed(std::uint64_t seed) {
    lua_pushcfunction(L_, seed_random);
    lua_pushinteger(L_, static_cast<lua_Integer>(seed));
    protected_call(L_, 1, 0);
    Recordings::of(L_).script_seed = seed;
}

void LuaHost::set_args(const std::string& script, const std::vector<std::string>& args) {
    lua_createtable(L_, static_cast<int>(args.size()), 1);
    lua_pushstring(L_, script.c_str());
    lua_rawseti(L_, -2, 0);
    for (size_t i = 0; i < args.size(); ++i) {
        lua_pushstring(L_, args[i].c_str());
        lua_rawseti(L_, -2, static_cast<lua_Integer>(i + 1));
    }
    raw_setglobal(L_, "arg");
    Recordings::of(L_).script_args = args;
}

void LuaHost::set_reporter(std::function<void(const std::string&)> fn) {
    using Reporter = std::function<void(const std::string&)>;
    register_type<Reporter>(L_, "gaitlab.Reporter", nullptr);
    new_object<Reporter>(L_, "gaitlab.Reporter", std::move(fn));
    lua_setfield(L_, LUA_REGISTRYINDEX, kReporterKey);
}

void LuaHost::set_reload_interval(double seconds) {
    Reloader::of(L_).set_interval(seconds);
}

double LuaHost::pump() {
    return Playback::of(L_).pump(L_);
}

int LuaHost::playing() const {
    return Playback::of(L_).playing();
}

int LuaHost::pause_all() {
    Playback& p = Playback::of(L_);
    const int n = p.playing();
    p.pause_all(L_, "");
    return n;
}

void LuaHost::set_clock(std::function<double()> now) {
    Playback::of(L_).clock = now ? std::move(now) : WallClock(steady_seconds);
}

void LuaHost::set_pump_slice(double seconds) {
    Playback::of(L_).slice = seconds;
}

void LuaHost::set_progress(std::function<void(const RunProgress&)> fn) {
    Playback::of(L_).progress = std::move(fn);
}

void LuaHost::run_file(const std::string& path) {
    std::string source;
    try {
        source = read_file(path);  // bounded, and never a FIFO or a device
    } catch (const ReadError& e) {
        throw ScriptError(e.what(), path, 0, "");
    }
    Recordings& r = Recordings::of(L_);
    // the recorded script: keep the very code that runs for the run folders
    if (!r.settings.script.empty() && path == r.settings.script) r.script_source = source;
    load_source(L_, source, path);
    protected_call(L_, 0, 0);
}

void LuaHost::set_recording(RecordSettings settings) {
    Recordings::of(L_).settings = std::move(settings);
}

std::vector<std::string> LuaHost::run_folders() const {
    return Recordings::of(L_).folders();
}

void LuaHost::finish(const std::string& error) {
    Recordings::of(L_).finish(error);
}

void LuaHost::on_simulation(std::function<void(Simulation&, int)> fn) {
    Recordings::of(L_).on_created.push_back(std::move(fn));
}

void LuaHost::set_origin(Origin origin) {
    lua_pushinteger(L_, static_cast<lua_Integer>(origin));
    lua_setfield(L_, LUA_REGISTRYINDEX, kOriginKey);
}

Origin LuaHost::origin() const {
    return default_origin(L_);
}

void LuaHost::set_output(std::function<void(const std::string&)> fn) {
    Recordings::of(L_).output = std::move(fn);
}

void LuaHost::set_print(bool to_stdout) {
    Recordings::of(L_).print_to_stdout = to_stdout;
}

void LuaHost::run_string(const std::string& code, const std::string& name) {
    if (luaL_loadbufferx(L_, code.data(), code.size(), name.c_str(), "t") != LUA_OK) {
        std::string msg = to_string(L_, -1);
        lua_pop(L_, 1);
        throw ScriptError(msg, name, 0, "");
    }
    protected_call(L_, 0, 0);
}

void LuaHost::run_simulation_file(const std::string& path) {
    const std::string file = absolute_path(path);
    Recordings& r = Recordings::of(L_);
    if (!r.settings.script.empty() && path == r.settings.script) {
        // the run folders keep the simulation file and its parts as one folder that replays
        std::vector<ConfigFile> parts;
        r.script_source = normalized_config(file, parts);
        for (ConfigFile& f : parts)
            r.settings.files.push_back(std::move(f));
    }
    lua_pushcfunction(L_, run_simulation_file_of);
    lua_pushstring(L_, file.c_str());
    protected_call(L_, 1, 0);
}

int LuaHost::check_simulation_file(const std::string& path, double seconds, double cycle,
                                   double settle) {
    const std::string file = absolute_path(path);
    lua_pushcfunction(L_, check_simulation_file_of);
    lua_pushstring(L_, file.c_str());
    lua_pushnumber(L_, seconds);
    lua_pushnumber(L_, cycle);
    lua_pushnumber(L_, settle);
    protected_call(L_, 4, 1);
    const int warned = static_cast<int>(lua_tointeger(L_, -1));
    lua_pop(L_, 1);
    return warned;
}

}  // namespace gaitlab::scripting
