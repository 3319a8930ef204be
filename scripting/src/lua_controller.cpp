#include "lua_controller.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <regex>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/types.h"
#include "guard.h"
#include "hot_reload.h"
#include "lua_util.h"

namespace gaitlab::scripting {

LuaController::LuaController(lua_State* L, std::shared_ptr<LuaControllerClass> cls)
    : Controller(cls->def),
      L_(main_thread(L)),
      cls_(std::move(cls)),
      label_(fmt::format("controller '{}'", cls_->def.name)),
      class_version_(cls_->version) {
    cls_->instances.push_back(this);
}

void LuaController::release_box() {
    if (box_) *box_ = nullptr;  // the methods of an earlier self table reach nothing now
    box_ = nullptr;
    luaL_unref(L_, LUA_REGISTRYINDEX, box_ref_);
    box_ref_ = LUA_NOREF;
}

LuaController::~LuaController() {
    release_box();
    auto& v = cls_->instances;
    v.erase(std::remove(v.begin(), v.end(), this), v.end());
    luaL_unref(L_, LUA_REGISTRYINDEX, self_ref_);
    luaL_unref(L_, LUA_REGISTRYINDEX, snapshot_ref_);
}

ControllerRef LuaController::ref() const {
    if (cls_->origin.empty()) {
        throw SpecError(fmt::format(
            "controller '{}' is defined inside a script ({}:{}): a file can only name a "
            "controller loaded from its own file (gaitlab.controller.load) or a template",
            name(), cls_->file, cls_->line));
    }
    ControllerRef r = Controller::ref();
    r.kind = cls_->origin_kind;
    r.name = cls_->origin;
    return r;
}

void LuaController::take_snapshot() {
    drop_snapshot();
    if (cls_->snapshot_ref == LUA_NOREF || self_ref_ == LUA_NOREF) return;
    lua_rawgeti(L_, LUA_REGISTRYINDEX, cls_->snapshot_ref);
    lua_rawgeti(L_, LUA_REGISTRYINDEX, self_ref_);
    call(1, 1, kLoadInstructionBudget, " in snapshot");
    snapshot_ref_ = luaL_ref(L_, LUA_REGISTRYINDEX);
}

void LuaController::drop_snapshot() {
    luaL_unref(L_, LUA_REGISTRYINDEX, snapshot_ref_);
    snapshot_ref_ = LUA_NOREF;
}

void LuaController::migrate() {
    class_version_ = cls_->version;
    const ControllerDef old = def();
    const ControllerDef& now = cls_->def;
    // parameters by name, clamped into their new range; new ones take their default
    std::vector<double> params;
    for (const ParamDef& p : now.params) {
        const int i = find_param(p.name);
        params.push_back(i < 0 ? p.default_value : std::clamp(param(i), p.min, p.max));
    }
    if (self_ref_ != LUA_NOREF) {
        lua_State* L = L_;
        lua_rawgeti(L, LUA_REGISTRYINDEX, self_ref_);
        for (const ParamDef& p : old.params) {
            const bool kept = std::any_of(now.params.begin(), now.params.end(),
                                          [&](const ParamDef& q) { return q.name == p.name; });
            if (!kept) {
                lua_pushnil(L);
                raw_setfield(L, -2, p.name.c_str());
            }
        }
        // values by name: kept arrays stay, removed ones go, new ones start at zero
        for (const std::string& v : old.values) {
            if (std::find(now.values.begin(), now.values.end(), v) == now.values.end()) {
                lua_pushnil(L);
                raw_setfield(L, -2, v.c_str());
            }
        }
        for (const std::string& v : now.values) {
            if (std::find(old.values.begin(), old.values.end(), v) != old.values.end()) continue;
            lua_createtable(L, joints(), 0);
            for (int m = 1; m <= joints(); ++m) {
                lua_pushnumber(L, 0);
                lua_rawseti(L, -2, m);
            }
            raw_setfield(L, -2, v.c_str());
        }
        lua_pop(L, 1);
    }
    redefine(now, std::move(params));
    push_params();
    if (cls_->on_reload_ref != LUA_NOREF && self_ref_ != LUA_NOREF) {
        lua_rawgeti(L_, LUA_REGISTRYINDEX, cls_->on_reload_ref);
        lua_rawgeti(L_, LUA_REGISTRYINDEX, self_ref_);
        if (snapshot_ref_ != LUA_NOREF) {
            lua_rawgeti(L_, LUA_REGISTRYINDEX, snapshot_ref_);
        } else {
            lua_pushnil(L_);
        }
        drop_snapshot();
        call(2, 0, kLoadInstructionBudget, " in on_reload");
        check_values(cls_->on_reload_ref);
    }
    drop_snapshot();
}

void LuaController::on_bind() {
    // a fresh instance table: parameters, the per-joint value arrays (zeros), joints, and the
    // methods that reach this controller through an upvalue
    lua_State* L = L_;
    release_box();
    luaL_unref(L, LUA_REGISTRYINDEX, self_ref_);
    lua_createtable(L, 0, static_cast<int>(def().params.size() + def().values.size() + 1));
    for (size_t k = 0; k < def().values.size(); ++k) {
        lua_createtable(L, joints(), 0);
        for (int m = 1; m <= joints(); ++m) {
            lua_pushnumber(L, 0);
            lua_rawseti(L, -2, m);
        }
        lua_setfield(L, -2, def().values[k].c_str());
    }
    lua_pushinteger(L, joints());
    lua_setfield(L, -2, "joints");

    set_methods();
    self_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
    pushed_version_ = ~std::uint64_t{0};
}

void LuaController::set_methods() {
    lua_State* L = L_;
    lua_createtable(L, 0, 1);  // metatable
    // keep these names in kControllerMethods: class definitions may not reuse them
    const luaL_Reg methods[] = {{"set_angle", l_set_angle},
                                {"joint_angle", l_joint_angle},
                                {"joint_velocity", l_joint_velocity},
                                {"joint_torque", l_joint_torque},
                                {"sensor", l_sensor},
                                {nullptr, nullptr}};
    lua_createtable(L, 0, 5);
    box_ = static_cast<LuaController**>(lua_newuserdatauv(L, sizeof(LuaController*), 0));
    *box_ = this;
    lua_pushvalue(L, -1);
    box_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
    luaL_setfuncs(L, methods, 1);
    lua_setfield(L, -2, "__index");
    lua_setmetatable(L, -2);
}

namespace {

// The copy of a controller's instance table, made breadth first with a work list in Lua tables
// (a linked list of 100 000 nodes is as deep as it is long: a copy that recursed once per level
// ran out of C stack). Tables shared or cyclic in the original are shared or cyclic in the
// copy. What cannot be copied is named by its path, rebuilt from the tables it was met in.
class DeepCopy {
  public:
    DeepCopy(lua_State* state, const std::string& controller) : L(state), controller_(controller) {
        luaL_checkstack(L, 32, "copying a controller");
        for (int* t : {&memo_, &queue_, &parent_, &key_, &as_key_}) {
            lua_newtable(L);
            *t = lua_gettop(L);
        }
    }

    /// Copies the table at `original`: its fields, and every table they reach, into the table
    /// at `copy` and new tables. Leaves the stack as it was.
    void copy_into(int original, int copy) {
        original = lua_absindex(L, original);
        copy = lua_absindex(L, copy);
        lua_pushvalue(L, original);
        lua_pushvalue(L, copy);
        lua_rawset(L, memo_);
        lua_pushvalue(L, original);
        lua_rawseti(L, queue_, ++queued_);
        for (lua_Integer next = 1; next <= queued_; ++next) {
            lua_rawgeti(L, queue_, next);
            const int from = lua_gettop(L);
            lua_pushvalue(L, from);
            lua_rawget(L, memo_);
            const int to = lua_gettop(L);
            lua_pushnil(L);
            while (lua_next(L, from) != 0) {
                const int key = lua_gettop(L) - 1;
                push_copy(key, from, key, true);
                push_copy(key + 1, from, key, false);
                lua_rawset(L, to);
                lua_pop(L, 1);  // the value; the key stays for lua_next
            }
            // a metatable (a class of methods, typically) is shared, not copied
            if (from != original && lua_getmetatable(L, from)) lua_setmetatable(L, to);
            lua_settop(L, from - 1);
        }
    }

  private:
    lua_State* L;
    const std::string& controller_;
    int memo_ = 0;    // original table -> its copy
    int queue_ = 0;   // the originals whose fields are still to copy, in the order met
    int parent_ = 0;  // original table -> the table it was met in
    int key_ = 0;     // original table -> the key it was met at
    int as_key_ = 0;  // original table -> true when it was met as a key
    lua_Integer queued_ = 0;

    // how a key shows in a path: .x, [3], ["a b"], [<table>]
    std::string key_text(int index) const {
        if (lua_type(L, index) == LUA_TSTRING) {
            size_t n = 0;
            const char* k = lua_tolstring(L, index, &n);
            const std::string key(k, n);
            const bool name = !key.empty() &&
                              (std::isalpha(static_cast<unsigned char>(key[0])) || key[0] == '_') &&
                              std::all_of(key.begin(), key.end(), [](char c) {
                                  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
                              });
            return name ? "." + key : "[\"" + key + "\"]";
        }
        if (lua_type(L, index) == LUA_TNUMBER) {
            lua_pushvalue(L, index);
            const std::string text = lua_tostring(L, -1);
            lua_pop(L, 1);
            return "[" + text + "]";
        }
        return "[<" + std::string(luaL_typename(L, index)) + ">]";
    }

    // the path of the field at key `key` of table `table`: self.plan.steps[1]
    std::string path(int table, int key, bool is_key) const {
        std::string text = key_text(key) + (is_key ? " (a key)" : "");
        lua_pushvalue(L, table);
        while (true) {  // from the table up to self, whose parent is none
            const int t = lua_gettop(L);
            lua_pushvalue(L, t);
            if (lua_rawget(L, parent_) == LUA_TNIL) {
                lua_pop(L, 2);
                break;
            }
            lua_pushvalue(L, t);
            lua_rawget(L, key_);
            lua_pushvalue(L, t);
            const bool met_as_key = lua_rawget(L, as_key_) != LUA_TNIL;
            text = key_text(-2) + (met_as_key ? " (a key)" : "") + text;
            lua_pop(L, 2);
            lua_replace(L, t);  // go on from the parent
        }
        return "self" + text;
    }

    [[noreturn]] void refuse(int table, int key, bool is_key, const std::string& what) const {
        throw SpecError(fmt::format(
            "controller '{}' cannot be copied: {} holds {} (only numbers, strings, booleans, "
            "tables and functions without upvalues can be copied; the copy would share it with "
            "the original)",
            controller_, path(table, key, is_key), what));
    }

    // pushes the copy of the value at `index`, the key `key` (itself when `is_key`) of table
    // `table`; a table not met before gets an empty copy, filled when its turn in the queue
    // comes
    void push_copy(int index, int table, int key, bool is_key) {
        index = lua_absindex(L, index);
        switch (lua_type(L, index)) {
            case LUA_TNIL:
            case LUA_TBOOLEAN:
            case LUA_TNUMBER:
            case LUA_TSTRING:
            case LUA_TLIGHTUSERDATA:
                lua_pushvalue(L, index);
                return;
            case LUA_TFUNCTION: {
                // a function that keeps state of its own (upvalues other than _ENV) would be
                // shared by the original and the copy
                if (!lua_iscfunction(L, index)) {
                    for (int u = 1;; ++u) {
                        const char* name = lua_getupvalue(L, index, u);
                        if (!name) break;
                        lua_pop(L, 1);
                        if (std::string(name) != "_ENV") {
                            refuse(table, key, is_key, "a function with upvalues");
                        }
                    }
                } else if (lua_getupvalue(L, index, 1)) {
                    lua_pop(L, 1);
                    refuse(table, key, is_key, "a C function with upvalues");
                }
                lua_pushvalue(L, index);
                return;
            }
            case LUA_TTABLE:
                break;
            case LUA_TTHREAD:
                refuse(table, key, is_key, "a coroutine");
            default:
                refuse(table, key, is_key, std::string("a ") + luaL_typename(L, index));
        }
        lua_pushvalue(L, index);
        if (lua_rawget(L, memo_) != LUA_TNIL) return;  // met already: the same copy
        lua_pop(L, 1);
        lua_newtable(L);
        lua_pushvalue(L, index);
        lua_pushvalue(L, -2);
        lua_rawset(L, memo_);
        for (const auto& [map, value] : {std::pair{parent_, table}, {key_, key}}) {
            lua_pushvalue(L, index);
            lua_pushvalue(L, value);
            lua_rawset(L, map);
        }
        if (is_key) {
            lua_pushvalue(L, index);
            lua_pushboolean(L, 1);
            lua_rawset(L, as_key_);
        }
        lua_pushvalue(L, index);
        lua_rawseti(L, queue_, ++queued_);
    }
};

}  // namespace

LuaController::LuaController(const LuaController& o)
    : Controller(o), L_(o.L_), cls_(o.cls_), label_(o.label_), class_version_(o.class_version_) {
    if (o.self_ref_ != LUA_NOREF) {
        lua_State* L = L_;
        luaL_checkstack(L, 8, "copying a controller");
        const int top = lua_gettop(L);
        try {
            DeepCopy copy(L, name());
            lua_rawgeti(L, LUA_REGISTRYINDEX, o.self_ref_);
            const int self = lua_gettop(L);
            // the instance table itself: its fields copied, its methods made anew for this
            // controller (the original's reach the original)
            lua_newtable(L);
            const int mine = lua_gettop(L);
            copy.copy_into(self, mine);
            lua_settop(L, mine);
            set_methods();
            self_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
        } catch (...) {
            lua_settop(L, top);
            release_box();
            throw;
        }
        lua_settop(L, top);
    }
    pushed_version_ = o.pushed_version_;
    cls_->instances.push_back(this);
}

std::unique_ptr<Controller> LuaController::clone() const {
    return std::unique_ptr<Controller>(new LuaController(*this));
}

std::unique_ptr<Controller> LuaController::fresh_copy() const {
    auto c = std::make_unique<LuaController>(L_, cls_);
    // parameters by name, as a reload keeps them
    for (const ParamDef& p : c->def().params) {
        const int i = find_param(p.name);
        if (i >= 0) c->set_param(p.name, std::clamp(param(i), p.min, p.max));
    }
    return c;
}

void LuaController::push_params() {
    lua_rawgeti(L_, LUA_REGISTRYINDEX, self_ref_);
    for (size_t i = 0; i < def().params.size(); ++i) {
        lua_pushnumber(L_, param(static_cast<int>(i)));
        raw_setfield(L_, -2, def().params[i].name.c_str());
    }
    lua_pop(L_, 1);
    pushed_version_ = param_version();
}

void LuaController::call(int nargs, int nresults, long long budget, const char* suffix) {
    const Budget limit(L_, budget, label_, suffix);
    std::optional<ScriptError> placed;
    try {
        protected_call(L_, nargs, nresults);
        return;
    } catch (const ScriptError& e) {
        // errors raised inside Lua's own C functions carry no place ("attempt to yield from
        // outside a coroutine"), and running out of memory none at all: say where, and whose
        const std::string message = e.what();
        static const std::regex located(R"(^[^:\n]+:[0-9]+: )");
        if (std::regex_search(message, located) || message.rfind(label_, 0) == 0) throw;
        const std::string where =
            e.line() > 0 ? fmt::format("{}:{}: ", e.file(), e.line()) : label_ + ": ";
        placed.emplace(where + message, e.file(), e.line(), e.traceback());
    }
    throw *placed;
}

void LuaController::check_values(int function_ref) {
    if (def().values.empty()) return;
    lua_rawgeti(L_, LUA_REGISTRYINDEX, self_ref_);
    for (const std::string& v : def().values) {
        if (raw_getfield(L_, -1, v) != LUA_TTABLE) {
            const std::string got = type_name(L_, -1);
            lua_pop(L_, 2);
            // the line of the assignment is gone once the function has returned: the function's
            // own definition is the closest place to name (not the class's, which may be far)
            std::string file = cls_->file;
            int line = cls_->line;
            lua_Debug ar;
            if (lua_rawgeti(L_, LUA_REGISTRYINDEX, function_ref) != LUA_TFUNCTION) {
                lua_pop(L_, 1);
            } else if (lua_getinfo(L_, ">S", &ar) && ar.linedefined > 0) {
                file = ar.source[0] == '@' ? ar.source + 1 : ar.short_src;
                line = ar.linedefined;
            }
            throw ScriptError(fmt::format("{}:{}: controller '{}': self.{} must stay a table (one "
                                          "number per joint), got {}",
                                          file, line, name(), v, got),
                              file, line, "");
        }
        lua_pop(L_, 1);
    }
    lua_pop(L_, 1);
}

void LuaController::step(ControlIO& io) {
    if (class_version_ != cls_->version) migrate();
    if (pushed_version_ != param_version()) push_params();
    lua_rawgeti(L_, LUA_REGISTRYINDEX, cls_->step_ref);
    lua_rawgeti(L_, LUA_REGISTRYINDEX, self_ref_);
    lua_pushnumber(L_, io.dt());
    struct Stepping {  // io_ is set only while step runs, whatever happens
        ControlIO*& io;
        ~Stepping() { io = nullptr; }
    } stepping{io_};
    io_ = &io;
    call(2, 0, cls_->budget, " in one step");
    check_values(cls_->step_ref);
}

void LuaController::sync_values() const {
    if (self_ref_ == LUA_NOREF) return;
    lua_rawgeti(L_, LUA_REGISTRYINDEX, self_ref_);
    for (size_t k = 0; k < def().values.size(); ++k) {
        std::vector<double>& out = values_[k];
        // whatever the code left there: what is not a table (check_values fails the
        // controller after its step) keeps the last values read; entries that are not
        // numbers read as 0
        if (raw_getfield(L_, -1, def().values[k]) == LUA_TTABLE) {
            for (int m = 0; m < joints(); ++m) {
                lua_rawgeti(L_, -1, m + 1);
                out[static_cast<size_t>(m)] = lua_tonumber(L_, -1);
                lua_pop(L_, 1);
            }
        }
        lua_pop(L_, 1);
    }
    lua_pop(L_, 1);
}

namespace {

// the controller whose methods these are (upvalue 1 holds its box)
LuaController* self_of(lua_State* L) {
    auto* c = *static_cast<LuaController**>(lua_touserdata(L, lua_upvalueindex(1)));
    if (!c) throw Error("this controller is gone (its simulation and handles were removed)");
    return c;
}

// "WHAT 'name'" with the closest of `names` and the list of them ("(LISTED: a, b)"), or `none`
std::string unknown(const std::string& what, const std::string& name,
                    const std::vector<std::string>& names, const char* listed, const char* none) {
    std::string message = what + " '" + name + "'" + did_you_mean(name, names);
    if (names.empty()) return message + " (" + none + ")";
    message += std::string(" (") + listed + ":";
    for (size_t i = 0; i < names.size(); ++i)
        message += (i ? ", " : " ") + names[i];
    return message + ")";
}

std::string no_sensor(const ControlIO& io, const std::string& name) {
    std::vector<std::string> names;
    for (int k = 0; k < io.sensor_count(); ++k)
        names.push_back(io.sensor(k).name);
    return unknown("the controller's robot has no sensor", name, names, "its sensors",
                   "it has no sensors");
}

std::string no_channel(SensorKind kind, const std::string& channel) {
    std::vector<std::string> names;
    for (const SensorChannel& c : sensor_channels(kind))
        names.push_back(c.name);
    return unknown(std::string(to_string(kind)) + " sensors have no channel", channel, names,
                   "channels", "no channels");
}

// a string argument as luaL_checkstring takes it (a number converts)
std::string check_text(lua_State* L, int arg) {
    if (!lua_isstring(L, arg)) {
        throw ArgError(arg, "string expected, got " + type_name(L, arg));
    }
    return to_string(L, arg);
}

void push_reading(lua_State* L, const SensorChannel& c, double value) {
    if (c.boolean) {
        lua_pushboolean(L, value != 0);
    } else {
        lua_pushnumber(L, to_user_units(c, value));
    }
}

int check_joint(lua_State* L, const Controller& c) {
    const long long m = check_integer(L, 2);
    if (m < 1 || m > c.joints()) throw ArgError(2, "joint number out of range");
    return static_cast<int>(m - 1);
}

// the step the controller is in: `method` may only be called while it steps
ControlIO& current_step(ControlIO* io, const char* method) {
    if (!io) throw Error(fmt::format("{} can only be called while the controller steps", method));
    return *io;
}

}  // namespace

int LuaController::l_set_angle(lua_State* L) {
    return protect(L, [&] {
        LuaController* c = self_of(L);
        const int m = check_joint(L, *c);
        const double deg = check_number(L, 3);
        if (!std::isfinite(deg)) throw ArgError(3, "finite number of degrees expected");
        current_step(c->io_, "set_angle").set_target(m, deg_to_rad(deg));
        return 0;
    });
}

int LuaController::l_joint_angle(lua_State* L) {
    return protect(L, [&] {
        LuaController* c = self_of(L);
        const int m = check_joint(L, *c);
        lua_pushnumber(L, rad_to_deg(current_step(c->io_, "joint_angle").angle(m)));
        return 1;
    });
}

int LuaController::l_joint_velocity(lua_State* L) {
    return protect(L, [&] {
        LuaController* c = self_of(L);
        const int m = check_joint(L, *c);
        lua_pushnumber(L, rad_to_deg(current_step(c->io_, "joint_velocity").velocity(m)));
        return 1;
    });
}

int LuaController::l_joint_torque(lua_State* L) {
    return protect(L, [&] {
        LuaController* c = self_of(L);
        const int m = check_joint(L, *c);
        lua_pushnumber(L, current_step(c->io_, "joint_torque").torque(m));
        return 1;
    });
}

int LuaController::l_sensor(lua_State* L) {
    return protect(L, [&] {
        LuaController* c = self_of(L);
        const std::string name = check_text(L, 2);
        std::optional<std::string> channel;
        if (!lua_isnoneornil(L, 3)) channel = check_text(L, 3);
        const ControlIO& io = current_step(c->io_, "sensor");
        const int k = io.find_sensor(name);
        if (k < 0) throw ArgError(2, no_sensor(io, name));
        const SensorSpec& spec = io.sensor(k);
        const auto& channels = sensor_channels(spec.kind);
        int ch = -1;
        if (channel) {
            ch = find_sensor_channel(spec.kind, *channel);
            if (ch < 0) throw ArgError(3, no_channel(spec.kind, *channel));
        }
        // a switched-off sensor reads nil: its last values are stale
        if (!spec.enabled) {
            lua_pushnil(L);
            return 1;
        }
        const double* values = io.sensor_values(k);
        if (ch >= 0) {
            push_reading(L, channels[static_cast<size_t>(ch)], values[ch]);
            return 1;
        }
        lua_createtable(L, 0, static_cast<int>(channels.size()));
        for (size_t i = 0; i < channels.size(); ++i) {
            push_reading(L, channels[i], values[i]);
            lua_setfield(L, -2, channels[i].name.c_str());
        }
        return 1;
    });
}

}  // namespace gaitlab::scripting
