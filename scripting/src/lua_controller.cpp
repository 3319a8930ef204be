#include "lua_controller.h"

#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/types.h"

namespace gaitlab::scripting {

LuaController::LuaController(lua_State* L, std::shared_ptr<LuaControllerClass> cls)
    : Controller(cls->def), L_(L), cls_(std::move(cls)) {}

LuaController::~LuaController() {
    luaL_unref(L_, LUA_REGISTRYINDEX, self_ref_);
}

void LuaController::on_bind() {
    // a fresh instance table: parameters, the per-joint value arrays (zeros), joints, and the
    // methods that reach this controller through an upvalue
    lua_State* L = L_;
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

    lua_createtable(L, 0, 1);  // metatable
    const luaL_Reg methods[] = {{"set_angle", l_set_angle},
                                {"angle", l_angle},
                                {"velocity", l_velocity},
                                {"torque", l_torque},
                                {nullptr, nullptr}};
    lua_createtable(L, 0, 4);
    lua_pushlightuserdata(L, this);
    luaL_setfuncs(L, methods, 1);
    lua_setfield(L, -2, "__index");
    lua_setmetatable(L, -2);
    self_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
    pushed_version_ = ~std::uint64_t{0};
}

void LuaController::push_params() {
    lua_rawgeti(L_, LUA_REGISTRYINDEX, self_ref_);
    for (size_t i = 0; i < def().params.size(); ++i) {
        lua_pushnumber(L_, param(static_cast<int>(i)));
        lua_setfield(L_, -2, def().params[i].name.c_str());
    }
    lua_pop(L_, 1);
    pushed_version_ = param_version();
}

void LuaController::step(ControlIO& io) {
    if (pushed_version_ != param_version()) push_params();
    lua_rawgeti(L_, LUA_REGISTRYINDEX, cls_->step_ref);
    lua_rawgeti(L_, LUA_REGISTRYINDEX, self_ref_);
    lua_pushnumber(L_, io.dt());
    io_ = &io;
    try {
        protected_call(L_, 2, 0);
    } catch (...) {
        io_ = nullptr;
        throw;
    }
    io_ = nullptr;
}

void LuaController::sync_values() const {
    if (self_ref_ == LUA_NOREF) return;
    lua_rawgeti(L_, LUA_REGISTRYINDEX, self_ref_);
    for (size_t k = 0; k < def().values.size(); ++k) {
        lua_getfield(L_, -1, def().values[k].c_str());
        std::vector<double>& out = values_[k];
        for (int m = 0; m < joints(); ++m) {
            lua_rawgeti(L_, -1, m + 1);
            out[static_cast<size_t>(m)] = lua_tonumber(L_, -1);
            lua_pop(L_, 1);
        }
        lua_pop(L_, 1);
    }
    lua_pop(L_, 1);
}

namespace {

// the controller and its current step; these helpers use only lauxlib errors, so no C++
// object is alive when they long-jump
LuaController* self_of(lua_State* L) {
    return static_cast<LuaController*>(lua_touserdata(L, lua_upvalueindex(1)));
}

int check_joint(lua_State* L, const Controller& c) {
    const lua_Integer m = luaL_checkinteger(L, 2);
    luaL_argcheck(L, m >= 1 && m <= c.joints(), 2, "joint number out of range");
    return static_cast<int>(m - 1);
}

}  // namespace

int LuaController::l_set_angle(lua_State* L) {
    LuaController* c = self_of(L);
    const int m = check_joint(L, *c);
    const double deg = luaL_checknumber(L, 3);
    if (!c->io_) return luaL_error(L, "set_angle can only be called while the controller steps");
    c->io_->set_target(m, deg_to_rad(deg));
    return 0;
}

int LuaController::l_angle(lua_State* L) {
    LuaController* c = self_of(L);
    const int m = check_joint(L, *c);
    if (!c->io_) return luaL_error(L, "angle can only be called while the controller steps");
    lua_pushnumber(L, rad_to_deg(c->io_->angle(m)));
    return 1;
}

int LuaController::l_velocity(lua_State* L) {
    LuaController* c = self_of(L);
    const int m = check_joint(L, *c);
    if (!c->io_) return luaL_error(L, "velocity can only be called while the controller steps");
    lua_pushnumber(L, rad_to_deg(c->io_->velocity(m)));
    return 1;
}

int LuaController::l_torque(lua_State* L) {
    LuaController* c = self_of(L);
    const int m = check_joint(L, *c);
    if (!c->io_) return luaL_error(L, "torque can only be called while the controller steps");
    lua_pushnumber(L, c->io_->torque(m));
    return 1;
}

}  // namespace gaitlab::scripting
