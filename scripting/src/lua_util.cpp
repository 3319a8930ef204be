#include "lua_util.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

namespace gaitlab::scripting {

namespace {

// nan, inf or -inf, as Lua's tostring writes them
const char* lua_number_name(double d) {
    if (std::isnan(d)) return "nan";
    return d > 0 ? "inf" : "-inf";
}

}  // namespace

std::string type_name(lua_State* L, int index) {
    if (luaL_getmetafield(L, index, "__name") == LUA_TSTRING) {
        std::string name = to_string(L, -1);
        lua_pop(L, 1);
        return name;
    }
    if (lua_type(L, index) == LUA_TLIGHTUSERDATA) return "light userdata";
    return luaL_typename(L, index);
}

lua_State* main_thread(lua_State* L) {
    lua_rawgeti(L, LUA_REGISTRYINDEX, LUA_RIDX_MAINTHREAD);
    lua_State* main = lua_tothread(L, -1);
    lua_pop(L, 1);
    return main;
}

void load_source(lua_State* L, std::string_view code, const std::string& chunk) {
    if (code.substr(0, 3) == "\xEF\xBB\xBF") code.remove_prefix(3);
    if (!code.empty() && code[0] == '#') {
        const size_t eol = code.find('\n');
        code.remove_prefix(eol == std::string_view::npos ? code.size() : eol);
    }
    const std::string name = "@" + chunk;
    if (luaL_loadbufferx(L, code.data(), code.size(), name.c_str(), "t") != LUA_OK) {
        std::string msg = to_string(L, -1);
        lua_pop(L, 1);
        throw ScriptError(located_load_error(msg, chunk), chunk, 0, "");
    }
}

std::string located_load_error(const std::string& message, const std::string& chunk) {
    if (message.rfind(chunk + ":", 0) == 0) return message;  // a syntax error: FILE:LINE: ...
    // the parser's own limits say no place ("C stack overflow"): name the file, and why
    if (message.find("C stack overflow") != std::string::npos) {
        return chunk + ": " + message +
               " (the code nests too deep to read: more than about 200 levels of parentheses, "
               "tables, blocks or function calls in one expression)";
    }
    if (message.find("binary chunk") != std::string::npos) {
        return chunk +
               ": a compiled Lua chunk (luac's output): gaitlab reads Lua source only "
               "(give the .lua file it was compiled from)";
    }
    return chunk + ": " + message;
}

Origin default_origin(lua_State* L) {
    lua_getfield(L, LUA_REGISTRYINDEX, kOriginKey);
    const lua_Integer o = lua_tointeger(L, -1);
    lua_pop(L, 1);
    switch (o) {
        case static_cast<lua_Integer>(Origin::console):
            return Origin::console;
        case static_cast<lua_Integer>(Origin::viewer):
            return Origin::viewer;
        default:
            return Origin::script;
    }
}

Origin opt_origin(lua_State* L, int arg) {
    if (lua_isnoneornil(L, arg)) return default_origin(L);
    const std::string o = check_string(L, arg);
    const auto parsed = parse_origin(o);
    if (!parsed || *parsed == Origin::file) {
        throw ArgError(arg, "'script', 'console' or 'viewer' expected, got '" + o + "'");
    }
    return *parsed;
}

void refuse_zero_byte(const std::string& path) {
    // the operating system would stop at the zero and open another file than the one checked
    if (path.find('\0') != std::string::npos) {
        throw Error("a path cannot contain a zero byte (got '" + path.substr(0, path.find('\0')) +
                    "\\x00...')");
    }
}

std::string script_path(lua_State* L, const std::string& path) {
    refuse_zero_byte(path);
    std::filesystem::path p(path);
    if (p.is_relative()) p = caller_dir(L) / p;
    return p.lexically_normal().string();
}

ScriptPath::ScriptPath(lua_State* L, std::string given)
    : given_(std::move(given)), path_(script_path(L, given_)) {
    if (std::filesystem::path(given_).is_relative()) base_ = caller_dir(L).lexically_normal();
}

std::string ScriptPath::shown(const std::string& resolved) const {
    if (resolved == path_) return given_;
    if (base_.empty()) return resolved;
    const std::filesystem::path rel = std::filesystem::path(resolved).lexically_relative(base_);
    return rel.empty() ? resolved : rel.string();
}

std::string ScriptPath::message(const IoError& e) const {
    const auto* w = dynamic_cast<const WriteError*>(&e);
    if (!w) return e.what();
    const auto show = [this](const std::string& p) { return p.empty() ? p : shown(p); };
    return WriteError(show(w->path()), w->reason(), show(w->folder()), show(w->part())).what();
}

void push_script_error(lua_State* L, const ScriptError& e) {
    lua_createtable(L, 0, 4);
    lua_pushstring(L, e.what());
    lua_setfield(L, -2, "message");
    lua_pushstring(L, e.file().c_str());
    lua_setfield(L, -2, "file");
    lua_pushinteger(L, e.line());
    lua_setfield(L, -2, "line");
    lua_pushstring(L, e.traceback().c_str());
    lua_setfield(L, -2, "traceback");
    lua_setfield(L, LUA_REGISTRYINDEX, kErrorOriginKey);
    lua_pushstring(L, e.what());
}

namespace {

// push_failure's body, called in protected mode with the Failure as light userdata: level 1 of
// the stack is the binding, level 2 the code that called it
int push_failure_value(lua_State* L) {
    const auto& f = *static_cast<const Failure*>(lua_touserdata(L, 1));
    switch (f.kind) {
        case Failure::script:
            push_script_error(L, *f.error);
            break;
        case Failure::located:
            luaL_where(L, 2);
            lua_pushstring(L, f.message);
            lua_concat(L, 2);
            break;
        case Failure::argument:
            lua_pushstring(L, f.message);
            break;
    }
    return 1;
}

}  // namespace

bool push_failure(lua_State* L, const Failure& f) {
    // neither push allocates: a light C function and a light userdata
    lua_pushcfunction(L, push_failure_value);
    lua_pushlightuserdata(L, const_cast<Failure*>(&f));
    return lua_pcall(L, 1, 1, 0) == LUA_OK;
}

void push_weak_table(lua_State* L, const char* mode) {
    lua_newtable(L);
    lua_createtable(L, 0, 1);
    lua_pushstring(L, mode);
    lua_setfield(L, -2, "__mode");
    lua_setmetatable(L, -2);
}

void push_table_field(lua_State* L, int index, const char* name, const char* mode) {
    index = lua_absindex(L, index);
    if (lua_getfield(L, index, name) == LUA_TTABLE) return;
    lua_pop(L, 1);
    if (mode) {
        push_weak_table(L, mode);
    } else {
        lua_newtable(L);
    }
    lua_pushvalue(L, -1);
    lua_setfield(L, index, name);
}

void number_object(lua_State* L) {
    const int object = lua_gettop(L);
    push_table_field(L, LUA_REGISTRYINDEX, kMadeKey, "k");  // an object's number goes with it
    lua_pushliteral(L, "count");
    lua_rawget(L, -2);
    const lua_Integer n = lua_tointeger(L, -1) + 1;
    lua_pop(L, 1);
    lua_pushliteral(L, "count");
    lua_pushinteger(L, n);
    lua_rawset(L, -3);
    lua_pushvalue(L, object);
    lua_pushinteger(L, n);
    lua_rawset(L, -3);
    lua_pop(L, 1);
}

namespace {

// pushes the table of `tname`'s handles (weak values), made on first use, and the key
void push_handles_and_key(lua_State* L, const char* tname, const HandleKey& key) {
    push_table_field(L, LUA_REGISTRYINDEX, kHandlesKey, nullptr);
    push_table_field(L, -1, tname, "v");
    lua_remove(L, -2);
    if (key.part.empty()) {
        lua_pushlightuserdata(L, const_cast<void*>(key.object));
    } else {
        lua_pushfstring(L, "%p %s", key.object, key.part.c_str());
    }
}

}  // namespace

bool find_handle(lua_State* L, const char* tname, const HandleKey& key) {
    push_handles_and_key(L, tname, key);
    lua_rawget(L, -2);
    if (luaL_testudata(L, -1, tname)) {
        lua_remove(L, -2);
        return true;
    }
    lua_pop(L, 2);
    return false;
}

void keep_handle(lua_State* L, const char* tname, const HandleKey& key) {
    const int handle = lua_gettop(L);
    push_handles_and_key(L, tname, key);
    lua_pushvalue(L, handle);
    lua_rawset(L, -3);
    lua_pop(L, 1);
}

void check_table(lua_State* L, int index) {
    if (!lua_istable(L, index)) {
        throw ArgError(index, "table expected, got " + type_name(L, index));
    }
}

double check_number(lua_State* L, int index) {
    int ok = 0;
    const double v = lua_tonumberx(L, index, &ok);
    if (!ok) throw ArgError(index, "number expected, got " + type_name(L, index));
    return v;
}

std::string read_integer(lua_State* L, int index, lua_Integer& out) {
    // a string is no number here, even "8", which lua_tointegerx would convert
    if (lua_type(L, index) != LUA_TNUMBER) return "integer expected, got " + type_name(L, index);
    int ok = 0;
    out = lua_tointegerx(L, index, &ok);
    if (ok) return "";
    const double d = lua_tonumber(L, index);
    // a whole number too large for an integer (1e19) is out of range, not fractional
    if (std::isfinite(d) && std::floor(d) == d) {
        return fmt::format("integer expected, got {} (beyond the 64-bit integers)", d);
    }
    // nan and inf are no fractions: name them as Lua prints them
    if (!std::isfinite(d)) return fmt::format("integer expected, got {}", lua_number_name(d));
    return "integer expected, got a fractional number";
}

long long check_integer(lua_State* L, int index) {
    int ok = 0;
    const lua_Integer v = lua_tointegerx(L, index, &ok);
    if (!ok) {
        if (lua_isnumber(L, index)) throw ArgError(index, "number has no integer representation");
        throw ArgError(index, "number expected, got " + type_name(L, index));
    }
    return v;
}

std::string check_string(lua_State* L, int index) {
    if (lua_type(L, index) != LUA_TSTRING) {
        throw ArgError(index, "string expected, got " + type_name(L, index));
    }
    return to_string(L, index);
}

std::filesystem::path caller_dir(lua_State* L) {
    lua_Debug ar;
    for (int level = 1; lua_getstack(L, level, &ar); ++level) {
        lua_getinfo(L, "S", &ar);
        if (ar.source[0] == '@') return std::filesystem::path(ar.source + 1).parent_path();
    }
    return {};
}

void push_vec3(lua_State* L, const Vec3& v) {
    lua_createtable(L, 0, 3);
    lua_pushnumber(L, v.x);
    lua_setfield(L, -2, "x");
    lua_pushnumber(L, v.y);
    lua_setfield(L, -2, "y");
    lua_pushnumber(L, v.z);
    lua_setfield(L, -2, "z");
    luaL_setmetatable(L, "gaitlab.Vec3");
}

void push_quat(lua_State* L, const Quat& q) {
    lua_createtable(L, 0, 4);
    lua_pushnumber(L, q.w);
    lua_setfield(L, -2, "w");
    lua_pushnumber(L, q.x);
    lua_setfield(L, -2, "x");
    lua_pushnumber(L, q.y);
    lua_setfield(L, -2, "y");
    lua_pushnumber(L, q.z);
    lua_setfield(L, -2, "z");
}

void set_body_state(lua_State* L, const BodyState& s) {
    push_vec3(L, s.pose.position);
    lua_setfield(L, -2, "position");
    push_quat(L, s.pose.orientation);
    lua_setfield(L, -2, "orientation");
    push_vec3(L, s.linear_velocity);
    lua_setfield(L, -2, "velocity");
}

Fields::Fields(lua_State* L, int index, int arg, std::initializer_list<const char*> allowed)
    : L_(L), index_(lua_absindex(L, index)), arg_(arg) {
    if (!lua_istable(L, index_)) throw ArgError(arg, "table expected, got " + type_name(L, index_));
    std::vector<std::string> names(allowed.begin(), allowed.end());
    lua_pushnil(L);
    while (lua_next(L, index_) != 0) {
        lua_pop(L, 1);
        if (lua_type(L, -1) != LUA_TSTRING) {
            const std::string t = type_name(L, -1);
            lua_pop(L, 1);
            throw ArgError(arg, "unexpected " + t + " key (fields are named)");
        }
        const std::string key = to_string(L, -1);
        if (std::find(names.begin(), names.end(), key) == names.end()) {
            lua_pop(L, 1);
            throw ArgError(arg, "unknown key '" + key + "'" + did_you_mean(key, names));
        }
    }
}

bool Fields::has(const char* key) const {
    const bool present = raw_getfield(L_, index_, key) != LUA_TNIL;
    lua_pop(L_, 1);
    return present;
}

int Fields::push(const char* key) const {
    return raw_getfield(L_, index_, key);
}

void Fields::fail(const char* key, const std::string& message) const {
    throw ArgError(arg_, std::string("field '") + key + "': " + message);
}

double Fields::number(const char* key, double fallback) const {
    if (push(key) == LUA_TNIL) {
        lua_pop(L_, 1);
        return fallback;
    }
    int ok = 0;
    const double v = lua_tonumberx(L_, -1, &ok);
    const std::string t = ok ? "" : type_name(L_, -1);
    lua_pop(L_, 1);
    if (!ok) fail(key, "number expected, got " + t);
    return v;
}

long long Fields::integer(const char* key, long long fallback) const {
    if (push(key) == LUA_TNIL) {
        lua_pop(L_, 1);
        return fallback;
    }
    lua_Integer v = 0;
    const std::string why = read_integer(L_, -1, v);
    lua_pop(L_, 1);
    if (!why.empty()) fail(key, why);
    return v;
}

std::string Fields::string(const char* key, const std::string& fallback) const {
    if (push(key) == LUA_TNIL) {
        lua_pop(L_, 1);
        return fallback;
    }
    if (lua_type(L_, -1) != LUA_TSTRING) {
        const std::string t = type_name(L_, -1);
        lua_pop(L_, 1);
        fail(key, "string expected, got " + t);
    }
    std::string s = to_string(L_, -1);
    lua_pop(L_, 1);
    return s;
}

bool Fields::boolean(const char* key, bool fallback) const {
    const int t = push(key);
    if (t == LUA_TNIL) {
        lua_pop(L_, 1);
        return fallback;
    }
    if (t != LUA_TBOOLEAN) {
        const std::string n = type_name(L_, -1);
        lua_pop(L_, 1);
        fail(key, "boolean expected, got " + n);
    }
    const bool b = lua_toboolean(L_, -1);
    lua_pop(L_, 1);
    return b;
}

Vec3 Fields::vec3(const char* key, const Vec3& fallback) const {
    const int t = push(key);
    if (t == LUA_TNIL) {
        lua_pop(L_, 1);
        return fallback;
    }
    if (t != LUA_TTABLE) {
        const std::string n = type_name(L_, -1);
        lua_pop(L_, 1);
        fail(key, "vector expected ({x, y, z}), got " + n);
    }
    double c[3];
    numbers(key, {"x", "y", "z"}, "vector", c);
    return {c[0], c[1], c[2]};
}

void Fields::numbers(const char* key, std::initializer_list<const char*> names, const char* what,
                     double* out) const {
    const int table = lua_gettop(L_);
    const auto n = static_cast<lua_Integer>(names.size());
    const std::vector<std::string> keys(names.begin(), names.end());
    const std::string shape = "{" + fmt::format("{}", fmt::join(keys, ", ")) + "}";
    const char* count_words[] = {"", "one", "two", "three", "four"};
    const std::string count = n < 5 ? count_words[n] : std::to_string(n);
    // every key is a component's name or place: a fourth number or a key 'w' would otherwise be
    // dropped without a word, where every other unknown key is an error
    lua_Integer given = 0;  // keys that are not names: the numbers given by place
    bool extra = false;
    std::optional<std::string> unknown;  // the first in byte order, whatever order next gives
    lua_pushnil(L_);
    while (lua_next(L_, table) != 0) {
        lua_pop(L_, 1);
        if (lua_type(L_, -1) == LUA_TSTRING) {
            std::string name = to_string(L_, -1);
            if (std::find(keys.begin(), keys.end(), name) == keys.end() &&
                (!unknown || name < *unknown)) {
                unknown = std::move(name);
            }
            continue;
        }
        ++given;
        if (!lua_isinteger(L_, -1) || lua_tointeger(L_, -1) < 1 || lua_tointeger(L_, -1) > n) {
            extra = true;
        }
    }
    if (unknown) {
        lua_settop(L_, table - 1);
        fail(key, fmt::format("unknown key '{}' (a {}'s keys are {} and {})", *unknown, what,
                              fmt::join(keys.begin(), keys.end() - 1, ", "), keys.back()));
    }
    if (extra) {
        lua_settop(L_, table - 1);
        fail(key, fmt::format("{} numbers expected ({}), got {}", n, shape, given));
    }
    lua_Integer i = 0;
    for (const char* name : names) {
        ++i;
        const bool named = raw_getfield(L_, table, name) != LUA_TNIL;
        if (named) {
            const bool placed = lua_rawgeti(L_, table, i) != LUA_TNIL;
            lua_pop(L_, 1);
            if (placed) {
                lua_settop(L_, table - 1);
                fail(key,
                     fmt::format("{} given twice: by name and as number {} of {}", name, i, shape));
            }
        } else {
            lua_pop(L_, 1);
            lua_rawgeti(L_, table, i);
        }
        int ok = 0;
        out[i - 1] = lua_tonumberx(L_, -1, &ok);
        lua_pop(L_, 1);
        if (!ok) {
            lua_settop(L_, table - 1);
            fail(key, fmt::format("{} expected ({} with {} numbers)", what, shape, count));
        }
    }
    lua_pop(L_, 1);
}

}  // namespace gaitlab::scripting
