// Controllers written in Lua: a class made by gaitlab.controller{...}, and its instances, which
// the scheduler steps like any C++ controller. Their lifetime is bound to the Lua state.
#pragma once

#include <lua.hpp>

#include <memory>
#include <string>

#include "gaitlab/controller.h"

namespace gaitlab::scripting {

/// What gaitlab.controller{...} declares: the definition and the Lua functions.
struct LuaControllerClass {
    ControllerDef def;
    int step_ref = LUA_NOREF;  ///< registry reference to step(self, dt)
    std::string file;          ///< where the class was defined
    int line = 0;
};

class LuaController final : public Controller {
  public:
    LuaController(lua_State* L, std::shared_ptr<LuaControllerClass> cls);
    ~LuaController() override;

    void step(ControlIO& io) override;
    const LuaControllerClass& cls() const { return *cls_; }

  protected:
    void sync_values() const override;
    void on_bind() override;

  private:
    void push_params();
    static int l_set_angle(lua_State* L);
    static int l_angle(lua_State* L);
    static int l_velocity(lua_State* L);
    static int l_torque(lua_State* L);

    lua_State* L_;
    std::shared_ptr<LuaControllerClass> cls_;
    int self_ref_ = LUA_NOREF;  // the instance table passed to step as self
    std::uint64_t pushed_version_ = ~std::uint64_t{0};
    ControlIO* io_ = nullptr;  // set only while step runs
};

}  // namespace gaitlab::scripting
