#include "gaitlab/scripting/console.h"

#include <lua.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <new>

#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/terminal.h"
#include "lua_util.h"

namespace gaitlab::scripting {

namespace {

// the chunk name of typed lines: errors read "console:1: ..."
constexpr const char* kChunkName = "=console";
// lua.c's mark of an incomplete chunk: the syntax error is at the end of the input
constexpr std::string_view kEofMark = "<eof>";

void write_to(FILE* f, const std::string& text) {
    std::fwrite(text.data(), 1, text.size(), f);
    std::fflush(f);
}

// compiles `code`; pushes the function (LUA_OK) or the error message
int load(lua_State* L, const std::string& code) {
    return luaL_loadbufferx(L, code.data(), code.size(), kChunkName, "t");
}

bool incomplete(lua_State* L, int status) {
    if (status != LUA_ERRSYNTAX) return false;
    size_t len = 0;
    const char* msg = lua_tolstring(L, -1, &len);
    const std::string_view m(msg ? msg : "", msg ? len : 0);
    return m.size() >= kEofMark.size() && m.substr(m.size() - kEofMark.size()) == kEofMark;
}

// the host's origin for one typed line
class OriginScope {
  public:
    OriginScope(LuaHost& host, Origin origin) : host_(host), previous_(host.origin()) {
        host_.set_origin(origin);
    }
    ~OriginScope() { host_.set_origin(previous_); }
    OriginScope(const OriginScope&) = delete;
    OriginScope& operator=(const OriginScope&) = delete;

  private:
    LuaHost& host_;
    Origin previous_;
};

bool is_name_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
}

bool is_identifier(std::string_view s) {
    if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
    return std::all_of(s.begin(), s.end(), is_name_char);
}

constexpr const char* kKeywords[] = {"and",   "break", "do",       "else", "elseif", "end",
                                     "false", "for",   "function", "goto", "if",     "in",
                                     "local", "nil",   "not",      "or",   "repeat", "return",
                                     "then",  "true",  "until",    "while"};

// what completion found for one name: whether it is a function (it gets "(")
struct Candidates {
    std::vector<std::pair<std::string, bool>> names;
    void add(std::string name, bool function) { names.emplace_back(std::move(name), function); }
};

// the string keys of the table at `index` that are identifiers (functions only if
// `methods_only`)
void table_keys(lua_State* L, int index, bool methods_only, Candidates& out) {
    index = lua_absindex(L, index);
    lua_pushnil(L);
    while (lua_next(L, index) != 0) {
        if (lua_type(L, -2) == LUA_TSTRING) {
            const std::string key = to_string(L, -2);
            const bool function = lua_isfunction(L, -1);
            // __index, __name ...: mechanics, not fields
            if (is_identifier(key) && key.rfind("__", 0) != 0 && (function || !methods_only)) {
                out.add(key, function);
            }
        }
        lua_pop(L, 1);
    }
}

// pushes the table an object's __index gives its methods from, or nothing (returns false):
// __index itself when a table, or the methods table a gaitlab type keeps as the first upvalue
// of its __index function (register_type_with_fields)
bool push_index_table(lua_State* L, int index) {
    if (!lua_getmetatable(L, index)) return false;
    lua_pushliteral(L, "__index");
    lua_rawget(L, -2);
    lua_remove(L, -2);
    if (lua_istable(L, -1)) return true;
    if (lua_iscfunction(L, -1) && lua_getupvalue(L, -1, 1) != nullptr) {
        lua_remove(L, -2);
        if (lua_istable(L, -1)) return true;
    }
    lua_pop(L, 1);
    return false;
}

// a controller's parameters are its fields (ctl.amplitude): its binding ctl:params() lists them
// (C++, no Lua code runs)
void controller_params(lua_State* L, Candidates& out) {
    if (!push_index_table(L, -1)) return;
    lua_getfield(L, -1, "params");
    lua_remove(L, -2);
    if (!lua_iscfunction(L, -1)) {
        lua_pop(L, 1);
        return;
    }
    lua_pushvalue(L, -2);
    try {
        protected_call(L, 1, 1);
    } catch (const ScriptError&) {
        return;  // a removed controller lists nothing
    }
    if (lua_istable(L, -1)) table_keys(L, -1, false, out);
    lua_pop(L, 1);
}

// the completions of the value on top (popped)
void value_keys(lua_State* L, bool methods_only, Candidates& out) {
    // a table's own keys, then those its metatables' __index tables give, a few levels deep
    for (int level = 0; level < 8; ++level) {
        const int t = lua_type(L, -1);
        if (t == LUA_TTABLE) table_keys(L, -1, methods_only, out);
        if (t == LUA_TUSERDATA && !methods_only) {
            const int name = luaL_getmetafield(L, -1, "__name");
            const bool controller =
                name == LUA_TSTRING && std::strcmp(lua_tostring(L, -1), "gaitlab.Controller") == 0;
            if (name != LUA_TNIL) lua_pop(L, 1);
            if (controller) controller_params(L, out);
        }
        if (t != LUA_TTABLE && t != LUA_TUSERDATA) break;
        if (!push_index_table(L, -1)) break;
        lua_remove(L, -2);
    }
    lua_pop(L, 1);
}

// replaces the value on top by its field `name`, found without calling Lua code: raw fields,
// then the __index tables of its metatables (nil if none)
void raw_field(lua_State* L, const std::string& name) {
    for (int level = 0; level < 8; ++level) {
        if (lua_istable(L, -1)) {
            lua_pushlstring(L, name.data(), name.size());
            if (lua_rawget(L, -2) != LUA_TNIL) {
                lua_remove(L, -2);
                return;
            }
            lua_pop(L, 1);
        } else if (!lua_isuserdata(L, -1)) {
            break;
        }
        if (!push_index_table(L, -1)) break;
        lua_remove(L, -2);
    }
    lua_pop(L, 1);
    lua_pushnil(L);
}

}  // namespace

Console::Console(LuaHost& host) : host_(host) {}

void Console::set_writers(Writer out, Writer err) {
    out_ = std::move(out);
    err_ = std::move(err);
}

const char* Console::prompt() const {
    return buffer_.empty() ? "> " : ">> ";
}

void Console::discard() {
    buffer_.clear();
}

void Console::write_error(const std::string& text) const {
    // a message quotes names and values the session typed: written as terminal text
    std::string t = terminal_text(text);
    if (t.empty() || t.back() != '\n') t += '\n';
    if (err_) {
        err_(t);
    } else {
        write_to(stderr, t);
    }
}

Console::Status Console::feed(std::string_view line) {
    lua_State* L = host_.state();
    const int top = lua_gettop(L);
    // an interrupt that came while the prompt waited is not meant for this line
    host_.clear_interrupt();
    Status status = Status::rejected;
    const bool first = buffer_.empty();
    try {
        std::string chunk;
        bool loaded = false;
        if (buffer_.empty()) {
            // "=expr" is "return expr" (lua 5.3's form); a bare line is tried as an
            // expression first, as lua.c's addreturn does
            const bool equals = !line.empty() && line[0] == '=';
            chunk = equals ? "return " + std::string(line.substr(1)) : std::string(line);
            if (!equals) {
                if (load(L, "return " + chunk) == LUA_OK) {
                    loaded = true;
                } else {
                    lua_pop(L, 1);
                }
            }
        } else {
            chunk = buffer_ + "\n" + std::string(line);
        }
        if (!loaded) {
            const int s = load(L, chunk);
            if (s != LUA_OK) {
                if (incomplete(L, s)) {
                    lua_settop(L, top);
                    buffer_ = std::move(chunk);
                    return Status::more;
                }
                std::string message = lua_isstring(L, -1) ? to_string(L, -1) : "syntax error";
                lua_settop(L, top);
                buffer_.clear();
                last_chunk_ = first ? std::string(line) : chunk;
                write_error(message);
                host_.clear_interrupt();
                return Status::rejected;
            }
        }
        last_chunk_ = first ? std::string(line) : chunk;
        buffer_.clear();
        run();
        status = Status::ran;
    } catch (const std::bad_alloc&) {
        buffer_.clear();
        write_error("not enough memory");
    }
    lua_settop(L, top);
    host_.clear_interrupt();
    return status;
}

void Console::run() {
    lua_State* L = host_.state();
    const int base = lua_gettop(L) - 1;  // below the chunk
    {
        const OriginScope console(host_, Origin::console);
        try {
            protected_call(L, 0, LUA_MULTRET);
        } catch (const ScriptError& e) {
            std::string text = e.what();
            if (!e.traceback().empty()) text += "\n" + e.traceback();
            write_error(text);
            lua_settop(L, base);
            return;
        } catch (const std::exception& e) {
            write_error(e.what());
            lua_settop(L, base);
            return;
        }
    }
    const int n = lua_gettop(L) - base;
    if (n == 0) return;
    // each result as gaitlab.pretty shows it (tostring if it is gone), tab-separated
    std::string text;
    for (int i = 1; i <= n; ++i) {
        if (i > 1) text += '\t';
        // read raw: this runs outside any protected call, where a metamethod's error would
        // end the process
        lua_getfield(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
        raw_getfield(L, -1, "gaitlab");
        lua_remove(L, -2);
        if (lua_istable(L, -1)) {
            raw_getfield(L, -1, "pretty");
            lua_remove(L, -2);
        }
        if (!lua_isfunction(L, -1)) {
            lua_pop(L, 1);
            raw_getglobal(L, "tostring");
        }
        lua_pushvalue(L, base + i);
        try {
            protected_call(L, 1, 1);
        } catch (const ScriptError& e) {
            if (!text.empty()) out_ ? out_(text + "\n") : write_to(stdout, text + "\n");
            write_error(std::string("cannot print the result: ") + e.what());
            lua_settop(L, base);
            return;
        }
        size_t len = 0;
        const char* s = lua_tolstring(L, -1, &len);
        if (s) {
            text.append(s, len);
        } else {
            text += luaL_typename(L, base + i);
        }
        lua_pop(L, 1);
    }
    lua_settop(L, base);
    text += '\n';
    if (out_) {
        out_(text);
    } else {
        write_to(stdout, text);
    }
}

std::size_t Console::word_start(std::string_view before) {
    std::size_t i = before.size();
    while (i > 0 && (is_name_char(before[i - 1]) || before[i - 1] == '.' || before[i - 1] == ':'))
        --i;
    return i;
}

std::vector<std::string> Console::complete(std::string_view before) const {
    const std::string word(before.substr(word_start(before)));
    // a number, or a method call in the middle (a:b.c): nothing to complete
    if (word.empty() || std::isdigit(static_cast<unsigned char>(word[0])) || word[0] == '.' ||
        word[0] == ':') {
        return {};
    }
    std::vector<std::string> names;
    std::vector<char> seps;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= word.size(); ++i) {
        if (i == word.size() || word[i] == '.' || word[i] == ':') {
            names.push_back(word.substr(start, i - start));
            if (i < word.size()) seps.push_back(word[i]);
            start = i + 1;
        }
    }
    for (std::size_t k = 0; k + 1 < seps.size(); ++k) {
        if (seps[k] == ':') return {};
    }
    const std::string prefix = names.back();
    const std::string head = word.substr(0, word.size() - prefix.size());
    const bool method = !seps.empty() && seps.back() == ':';

    lua_State* L = host_.state();
    const int top = lua_gettop(L);
    Candidates found;
    try {
        lua_pushglobaltable(L);
        if (names.size() == 1) {
            value_keys(L, false, found);
            for (const char* k : kKeywords)
                found.add(k, false);
        } else {
            for (std::size_t k = 0; k + 1 < names.size(); ++k) {
                if (!is_identifier(names[k])) {
                    lua_settop(L, top);
                    return {};
                }
                raw_field(L, names[k]);
            }
            value_keys(L, method, found);
        }
    } catch (const std::exception&) {
        lua_settop(L, top);
        return {};
    }
    lua_settop(L, top);

    std::vector<std::string> out;
    for (const auto& [name, function] : found.names) {
        if (name.compare(0, prefix.size(), prefix) != 0) continue;
        out.push_back(head + name + (function || method ? "(" : ""));
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace gaitlab::scripting
