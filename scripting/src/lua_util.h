// Helpers every binding file uses: argument checks in lauxlib's vocabulary, C++ objects in
// userdata, table fields with unknown-key detection, and the exception barrier.
//
// These sources run on two Lua cores: Debian's Lua built as C++ (liblua5.4-c++, linked by the
// gaitlab program), where a Lua error is a C++ exception that unwinds C++ frames, and the C Lua
// of an interpreter that does `require "gaitlab"` (the module, scripting/module/), where a Lua
// error is a longjmp that skips every C++ destructor on its way. So that both are correct:
//   - a binding is `return protect(L, [&] { ... })`: its body reports errors by throwing C++
//     exceptions (ArgError, Error ...), and protect raises them as Lua errors once the body's
//     objects are gone. Inside a body, nothing may raise a Lua error: no luaL_check*,
//     luaL_opt*, luaL_error, lua_error, lua_call, and no access that may run a metamethod
//     (tables that scripts give are read and written raw: raw_getfield, lua_rawgeti ...,
//     globals through raw_getglobal);
//   - Lua code is called with protected_call (lua_host.h), which turns its errors into
//     ScriptError;
//   - a C function that raises Lua errors itself (lauxlib checks, lua_error) has no C++ object
//     with a destructor alive when it does, and never lets a C++ exception out;
//   - no Lua function is called from a catch block (an error there would skip the end of the
//     handler): catch blocks keep what they need and the Lua calls come after them.
// The one exception is running out of memory inside a body, which the C core raises from
// any allocation: the body's objects are then not destroyed (docs/embedding.md says so).
#pragma once

#include <lua.hpp>

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gaitlab/error.h"
#include "gaitlab/event.h"
#include "gaitlab/files.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/suggest.h"
#include "gaitlab/types.h"
#include "gaitlab/xml.h"

namespace gaitlab::scripting {

/// A bad argument: becomes "bad argument #arg to 'fn' (message)".
class ArgError : public Error {
  public:
    ArgError(int arg, const std::string& message) : Error(message), arg_(arg) {}
    int arg() const { return arg_; }

  private:
    int arg_;
};

/// The main thread of L's state. C++ objects that call into Lua later (controllers, hooks of a
/// simulation) keep it, never the thread they were made on: a coroutine may be collected.
lua_State* main_thread(lua_State* L);

/// A load error as it should read: a syntax error already names "CHUNK:LINE:"; the parser's
/// other errors ("C stack overflow", "not enough memory") get "CHUNK: " and, for the nesting
/// limit, what it means.
std::string located_load_error(const std::string& message, const std::string& chunk);

/// Compiles `source` (text only) as the chunk "@`chunk`" and pushes it; a first line starting
/// with '#' (a shebang) and a UTF-8 byte order mark are skipped, as luaL_loadfile does, keeping
/// the line numbers. Throws ScriptError with the syntax error.
void load_source(lua_State* L, std::string_view source, const std::string& chunk);

/// The string at `index` (which must be a string), all of it: embedded zeros included, so a
/// name never quietly loses its tail.
inline std::string to_string(lua_State* L, int index) {
    size_t len = 0;
    const char* s = lua_tolstring(L, index, &len);
    return std::string(s, len);
}

/// t[key] without metamethods, for the table at `index`: pushes the value, returns its type.
/// Bindings read and write tables that scripts give (or may have given a metatable) only
/// this way, so no script code runs in the middle of a binding.
inline int raw_getfield(lua_State* L, int index, const char* key) {
    index = lua_absindex(L, index);
    lua_pushstring(L, key);
    return lua_rawget(L, index);
}

/// The same for a key held in a std::string, all of it (a zero byte included).
inline int raw_getfield(lua_State* L, int index, const std::string& key) {
    index = lua_absindex(L, index);
    lua_pushlstring(L, key.data(), key.size());
    return lua_rawget(L, index);
}

/// t[key] = value on top (popped), without metamethods.
inline void raw_setfield(lua_State* L, int index, const char* key) {
    index = lua_absindex(L, index);
    lua_pushstring(L, key);
    lua_insert(L, -2);
    lua_rawset(L, index);
}

/// The global `name` without metamethods (the interpreter that requires gaitlab may give its
/// globals a metatable, as strict.lua does): pushes it, returns its type.
inline int raw_getglobal(lua_State* L, const char* name) {
    lua_pushglobaltable(L);
    const int t = raw_getfield(L, -1, name);
    lua_remove(L, -2);
    return t;
}

/// The global `name` = the value on top (popped), without metamethods.
inline void raw_setglobal(lua_State* L, const char* name) {
    lua_pushglobaltable(L);
    lua_insert(L, -2);
    raw_setfield(L, -2, name);
    lua_pop(L, 1);
}

/// Pushes nil and `message` (a function's failure, as luaL_fileresult gives it); returns 2.
inline int push_fail(lua_State* L, const std::string& message) {
    lua_pushnil(L);
    lua_pushlstring(L, message.data(), message.size());
    return 2;
}

/// The type name Lua uses in its own messages (honours __name).
std::string type_name(lua_State* L, int index);

/// Registry key of the last ScriptError that crossed C++ into Lua (see push_script_error).
inline constexpr const char* kErrorOriginKey = "gaitlab.error_origin";

/// Registry key of the host's reporting hook (a std::function<void(const std::string&)> in a
/// userdata; see LuaHost::set_reporter).
inline constexpr const char* kReporterKey = "gaitlab.reporter";

/// Pushes a ScriptError's message as the Lua error value and keeps its file, line and
/// traceback in the registry, so the message handler of an enclosing protected_call reports
/// where it happened (e.g. inside a Lua controller stepped by sim:run), not where it resurfaced.
void push_script_error(lua_State* L, const ScriptError& e);

/// What a binding failed with, as protect() raises it (pointers into the exception, which
/// lives while its handler runs).
struct Failure {
    enum Kind { argument, script, located } kind;
    const char* message;                 ///< argument, located: the message
    const ScriptError* error = nullptr;  ///< script: the error
};

/// Pushes the error value of `f` in protected mode: for `located`, prefixed with the place of
/// the Lua code that called the binding (as luaL_error does); for `script`, its place kept for
/// the message handler (push_script_error). Returns false, with Lua's out-of-memory message
/// pushed instead, if the memory ran out.
bool push_failure(lua_State* L, const Failure& f);

/// Runs `body` (returning the number of results) and turns a C++ exception it throws into a
/// Lua error ("bad argument #N to 'fn' (...)" for ArgError) once the body's objects and the
/// exception are gone, so that nothing with a destructor is skipped (see the top of this
/// file). Exceptions that are not std::exception pass through: under Lua built as C++ those
/// are Lua's own errors.
template <class F>
int protect(lua_State* L, F&& body) {
    const int top = lua_gettop(L);
    int arg = 0;
    bool pushed = false;
    try {
        return body();
    } catch (const ArgError& e) {
        lua_settop(L, top);
        arg = e.arg();
        pushed = push_failure(L, {Failure::argument, e.what()});
    } catch (const ScriptError& e) {
        lua_settop(L, top);
        pushed = push_failure(L, {Failure::script, e.what(), &e});  // already says where
    } catch (const std::bad_alloc&) {
        lua_settop(L, top);
        pushed = push_failure(L, {Failure::located, "not enough memory"});
    } catch (const std::exception& e) {
        lua_settop(L, top);
        pushed = push_failure(L, {Failure::located, e.what()});
    }
    if (pushed && arg > 0) return luaL_argerror(L, arg, lua_tostring(L, -1));
    return lua_error(L);
}

/// Pushes a new table whose metatable's __mode is `mode` ("k", "v" or "kv").
void push_weak_table(lua_State* L, const char* mode);

/// Pushes the table in field `name` of the table at `index`, made and stored there first if the
/// field holds no table: weak as `mode` says (push_weak_table), or a plain table for nullptr.
void push_table_field(lua_State* L, int index, const char* name, const char* mode);

/// Registry key of the order in which a state made gaitlab's userdata: a table with weak keys
/// from each to its number (1 for the first), and under "count" the last number given. The
/// host's pairs visits such keys in that order (fixed_order.h).
inline constexpr const char* kMadeKey = "gaitlab.made";

/// Gives the userdata on top of the stack (not popped) the next number of its state's
/// kMadeKey. A userdata collected and made again is numbered again, as the newest.
void number_object(lua_State* L);

/// The number number_object gave the value at `index`, pushing nothing, given the kMadeKey
/// table at `made` (absolute); 0 if it has none (another value, or another library's userdata).
inline lua_Integer object_number(lua_State* L, int index, int made) {
    lua_pushvalue(L, index);
    lua_rawget(L, made);
    const lua_Integer n = lua_tointeger(L, -1);
    lua_pop(L, 1);
    return n;
}

/// Creates a userdata holding a T, with the metatable registered as `tname`, numbered by
/// number_object.
template <class T>
T* new_object(lua_State* L, const char* tname, T value) {
    void* p = lua_newuserdatauv(L, sizeof(T), 0);
    T* obj = new (p) T(std::move(value));
    luaL_setmetatable(L, tname);
    number_object(L);
    return obj;
}

/// The T held by the userdata at `index`, which must have metatable `tname`.
template <class T>
T& check_object(lua_State* L, int index, const char* tname) {
    void* p = luaL_testudata(L, index, tname);
    if (!p) throw ArgError(index, std::string(tname) + " expected, got " + type_name(L, index));
    return *static_cast<T*>(p);
}

/// What names an entity among the handles of one type: the address of an object its handle
/// keeps alive (the target of the shared_ptr it holds), and for a part of that object, which
/// part ("" for the object itself; a sensor's number, a group's joints).
struct HandleKey {
    const void* object;
    std::string part;

    bool operator==(const HandleKey& o) const { return object == o.object && part == o.part; }
};

/// The key of a handle that holds a shared_ptr: the object it points to.
template <class X>
HandleKey handle_key(const std::shared_ptr<X>& object) {
    return {object.get(), ""};
}

/// Registry key of the handles made by push_canonical: per type name, a table with weak values
/// from an entity's HandleKey to its handle.
inline constexpr const char* kHandlesKey = "gaitlab.handles";

/// Pushes the handle of type `tname` kept under `key` and returns true, if there is one that
/// lives (not destroyed by its __gc called by hand); pushes nothing and returns false otherwise.
bool find_handle(lua_State* L, const char* tname, const HandleKey& key);

/// Keeps the handle on top of the stack (not popped) under `key`, for as long as it lives.
void keep_handle(lua_State* L, const char* tname, const HandleKey& key);

/// Pushes the handle of the entity `value` stands for, named by handle_key(value) (an overload
/// beside each handle type): the userdata made for it before while that one lives, else a new
/// userdata holding `value` (type `tname`). So one entity has one handle, and handles compare
/// with == and index tables as the entities they stand for.
///
/// A key can name no other object while its handle lives: the handle keeps its object alive,
/// and once the handle is unreachable the collector clears it from the weak table before its
/// __gc releases the object, so a new object at a freed address never gets an old handle. A
/// handle destroyed by hand is skipped (find_handle). The handle's type adds an __eq comparing
/// keys (handle_eq) for the one case where two handles of one entity can both be reached: a
/// finalizer of the script's brings back a handle the table has already let go.
template <class T>
T* push_canonical(lua_State* L, const char* tname, T value) {
    const HandleKey key = handle_key(value);
    if (find_handle(L, tname, key)) return static_cast<T*>(lua_touserdata(L, -1));
    T* obj = new_object<T>(L, tname, std::move(value));
    keep_handle(L, tname, key);
    return obj;
}

/// __eq of handles of type `tname`: whether both operands are live handles of that type with
/// one key (push_canonical). Anything else (another type, a handle destroyed by hand) equals
/// nothing.
template <class T>
int handle_eq(lua_State* L, const char* tname) {
    const auto* a = static_cast<const T*>(luaL_testudata(L, 1, tname));
    const auto* b = static_cast<const T*>(luaL_testudata(L, 2, tname));
    lua_pushboolean(L, a && b && handle_key(*a) == handle_key(*b));
    return 1;
}

/// __gc of a T in userdata of type `tname` (upvalue 1): destroys it once, whatever it is called
/// with, then removes the metatable so nothing (not even a second __gc) reaches it again.
template <class T>
int destroy_object(lua_State* L) {
    void* p = luaL_testudata(L, 1, lua_tostring(L, lua_upvalueindex(1)));
    if (!p) return 0;
    static_cast<T*>(p)->~T();
    lua_pushnil(L);
    lua_setmetatable(L, 1);
    return 0;
}

/// Registers metatable `tname` with __gc destroying a T, __name, and the given methods as
/// __index (unless the methods table holds its own __index). The metatable is protected:
/// getmetatable(obj) gives `tname`, so scripts cannot call __gc or replace methods.
template <class T>
void register_type(lua_State* L, const char* tname, const luaL_Reg* methods,
                   const luaL_Reg* metamethods = nullptr) {
    luaL_newmetatable(L, tname);
    lua_pushstring(L, tname);
    lua_pushcclosure(L, destroy_object<T>, 1);
    lua_setfield(L, -2, "__gc");
    lua_pushstring(L, tname);
    lua_setfield(L, -2, "__metatable");
    if (metamethods) luaL_setfuncs(L, metamethods, 0);
    if (methods) {
        lua_getfield(L, -1, "__index");
        const bool has_index = !lua_isnil(L, -1);
        lua_pop(L, 1);
        if (!has_index) {
            lua_newtable(L);
            luaL_setfuncs(L, methods, 0);
            lua_setfield(L, -2, "__index");
        }
    }
    lua_pop(L, 1);
}

/// Registers `tname` as register_type does, for objects with fields computed on access: `index`
/// is __index, called with the methods table as its upvalue 1 (to fall back on), and
/// `metamethods` (__newindex, __tostring, ...) may be null.
template <class T>
void register_type_with_fields(lua_State* L, const char* tname, const luaL_Reg* methods,
                               lua_CFunction index, const luaL_Reg* metamethods) {
    luaL_newmetatable(L, tname);
    lua_newtable(L);
    luaL_setfuncs(L, methods, 0);
    lua_pushcclosure(L, index, 1);
    lua_setfield(L, -2, "__index");
    lua_pop(L, 1);
    register_type<T>(L, tname, nullptr, metamethods);
}

/// The one rule for an integer that a spec table holds, as a field or as an entry of a list: a
/// Lua number with an integer value (8, or 8.0), never a string. (Lua's own conversion,
/// lua_tointeger, would take "8" for 8; a count read from text is the script's to convert, with
/// tonumber.) Returns "" and sets `out` for such a value, else says why not as a field's
/// message does: "integer expected, got string", "... got a fractional number", "... got nan",
/// "... got 1e+19 (beyond the 64-bit integers)".
std::string read_integer(lua_State* L, int index, lua_Integer& out);

/// Checks that the value at `index` is a table; throws ArgError otherwise.
void check_table(lua_State* L, int index);
double check_number(lua_State* L, int index);
long long check_integer(lua_State* L, int index);
std::string check_string(lua_State* L, int index);

/// The folder of the innermost Lua file on the call stack ("" if none): relative paths that
/// scripts give are resolved against it.
std::filesystem::path caller_dir(lua_State* L);

/// An integer argument as an int: values beyond int's range saturate, so the spec's own range
/// check rejects them with the message it gives for any out-of-range count.
inline int saturate_int(long long v) {
    return static_cast<int>(
        std::clamp<long long>(v, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
}

/// Registry key of the origin of changes made without naming one (an integer: Origin).
inline constexpr const char* kOriginKey = "gaitlab.origin";

/// Who makes the changes that do not say (`ctl.x = v`, `sim:reset()` ...): the host's origin
/// (LuaHost::set_origin), "script" unless a front end runs the code.
Origin default_origin(lua_State* L);

/// Who makes a change (argument `arg`): "script", "console" or "viewer"; when absent, the
/// host's default_origin. Front ends pass theirs so that a replay can tell their changes apart.
Origin opt_origin(lua_State* L, int arg);

/// Throws Error for a path with a zero byte: the operating system would stop at the zero and
/// open another file than the one checked ("a path cannot contain a zero byte (got ...)").
void refuse_zero_byte(const std::string& path);

/// `path` as the calling script means it: relative paths are relative to the folder of the Lua
/// file that called the current C function (the working directory if none, e.g. in a REPL).
/// Throws Error for a path with a zero byte (the system would open another file).
std::string script_path(lua_State* L, const std::string& path);

/// A path a script gave to a function that writes it: where to write (as script_path resolves
/// it), and how messages show it and the files and folders around it — as the script wrote it.
class ScriptPath {
  public:
    /// Throws Error as script_path does.
    ScriptPath(lua_State* L, std::string given);
    /// The path to write: relative paths resolved against the calling script's folder.
    const std::string& path() const { return path_; }
    /// `resolved` (this path, a folder above it, a file next to it) as the script would write
    /// it: the given path itself, or relative to the script's folder if the given one was.
    std::string shown(const std::string& resolved) const;
    /// The message of a failed write with every path in it shown so: "cannot write
    /// runs/x/sim.xml: Permission denied", never a path the script did not write.
    std::string message(const IoError& e) const;

  private:
    std::string given_;
    std::string path_;
    std::filesystem::path base_;  // the script's folder; empty if paths are shown as resolved
};

/// The result of every save(path) function: runs `write` (which writes `path.path()`) and
/// pushes that path, or nil and the message of the IoError it threw (Lua's luaL_fileresult
/// convention), naming the file as the script gave it.
template <class F>
int file_written(lua_State* L, const ScriptPath& path, F&& write) {
    std::optional<std::string> failed;
    try {
        write();
    } catch (const IoError& e) {
        failed = path.message(e);
    }
    if (failed) return push_fail(L, *failed);
    lua_pushstring(L, path.path().c_str());
    return 1;
}

/// The result of every load(path) function: runs `read` (which reads a file and pushes one
/// value), or pushes nil and the message of the FormatError it threw.
template <class F>
int file_read(lua_State* L, F&& read) {
    const int top = lua_gettop(L);
    std::optional<std::string> failed;
    try {
        read();
    } catch (const FormatError& e) {
        failed = e.what();
    }
    if (!failed) return 1;
    lua_settop(L, top);
    return push_fail(L, *failed);
}

/// Pushes {x = , y = , z = } with the gaitlab.Vec3 metatable.
void push_vec3(lua_State* L, const Vec3& v);

/// Pushes {w = , x = , y = , z = }.
void push_quat(lua_State* L, const Quat& q);

/// Sets position, orientation and velocity of the table on top of the stack from a body's state.
void set_body_state(lua_State* L, const BodyState& s);

/// Reads the fields of a table argument; unknown keys are an error naming the closest valid one.
class Fields {
  public:
    Fields(lua_State* L, int index, int arg, std::initializer_list<const char*> allowed);

    bool has(const char* key) const;
    double number(const char* key, double fallback) const;
    /// An integer as read_integer reads it (a numeric string is refused).
    long long integer(const char* key, long long fallback) const;
    std::string string(const char* key, const std::string& fallback) const;
    bool boolean(const char* key, bool fallback) const;
    /// {x, y, z} or {x = , y = , z = }.
    Vec3 vec3(const char* key, const Vec3& fallback) const;
    /// The table on top of the stack (popped) as the numbers `names` ({a, b, c} or
    /// {a = , b = , c = }, into `out`), the value of field `key`: a number missing or not a
    /// number, a number too many and a key not in `names` are errors naming the field, `what`
    /// ("vector") saying what was expected.
    void numbers(const char* key, std::initializer_list<const char*> names, const char* what,
                 double* out) const;
    /// Pushes the field (any type) and returns its Lua type.
    int push(const char* key) const;
    lua_State* state() const { return L_; }
    int index() const { return index_; }
    int arg() const { return arg_; }

    /// "field 'key': <message>" as an ArgError for this argument.
    [[noreturn]] void fail(const char* key, const std::string& message) const;

  private:
    lua_State* L_;
    int index_;
    int arg_;
};

}  // namespace gaitlab::scripting
