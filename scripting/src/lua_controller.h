// Controllers written in Lua: a class made by gaitlab.controller{...}, and its instances, which
// the scheduler steps like any C++ controller. Their lifetime is bound to the Lua state.
#pragma once

#include <lua.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gaitlab/actuation.h"
#include "gaitlab/controller.h"

namespace gaitlab::scripting {

class LuaController;

/// The methods every Lua controller instance has (self:set_angle(m, deg), ...): parameter and
/// value names may not reuse them, nor "joints" (the group size).
inline constexpr const char* kControllerMethods[] = {"set_angle", "joint_angle", "joint_velocity",
                                                     "sensor", "joint_torque"};

/// Instructions one step may run before it is stopped, unless the class sets its own budget.
inline constexpr long long kDefaultInstructionBudget = 10'000'000;

/// What gaitlab.controller{...} declares: the definition and the Lua functions. A class
/// loaded from a file is the unit of hot reload: a new version replaces these fields in place
/// and increases `version`; its instances migrate at their next step.
struct LuaControllerClass {
    ControllerDef def;
    int step_ref = LUA_NOREF;                      ///< registry reference to step(self, dt)
    int snapshot_ref = LUA_NOREF;                  ///< snapshot(self) -> table, or LUA_NOREF
    int on_reload_ref = LUA_NOREF;                 ///< on_reload(self, snapshot), or LUA_NOREF
    long long budget = kDefaultInstructionBudget;  ///< instructions per step
    std::string file;                              ///< where the class was defined
    int line = 0;
    /// How an actuation file names this class: a controller file (origin = its absolute path)
    /// or a template (origin = its name); origin is "" for a class defined inside a script.
    ControllerRef::Kind origin_kind = ControllerRef::Kind::file;
    std::string origin;
    std::uint64_t version = 0;              ///< increases with every successful reload
    std::string reload_error;               ///< why the last reload failed ("" if it did not)
    std::vector<LuaController*> instances;  ///< live instances, for the snapshot hook
};

class LuaController final : public Controller {
  public:
    LuaController(lua_State* L, std::shared_ptr<LuaControllerClass> cls);
    ~LuaController() override;

    void step(ControlIO& io) override;
    ControllerRef ref() const override;
    /// A copy in the same Lua state: parameters, values and a deep copy of the instance
    /// table's plain data (numbers, strings, booleans, tables, nested and shared as they are;
    /// functions without upvalues are shared). Throws SpecError naming the controller and the
    /// field for a value that cannot be copied (a coroutine, a userdata, a function with
    /// upvalues: state the copy would share with the original).
    std::unique_ptr<Controller> clone() const override;
    /// A new instance of the same class, parameters at this one's values.
    std::unique_ptr<Controller> fresh_copy() const override;
    const LuaControllerClass& cls() const { return *cls_; }

    /// Calls the class's snapshot(self) and keeps the result for on_reload; throws ScriptError.
    /// Does nothing when the class has no snapshot hook or the instance is not bound.
    void take_snapshot();
    /// Drops a snapshot taken for a reload that did not happen.
    void drop_snapshot();

  protected:
    void sync_values() const override;
    void on_bind() override;

  private:
    LuaController(const LuaController& other);
    // creates the instance's methods (a metatable whose functions reach this controller
    // through a new box) and sets them on the table on top of the stack
    void set_methods();
    void push_params();
    // adopts the current version of the class: parameters and values kept by name
    void migrate();
    // calls the function below `nargs` arguments under `budget` instructions
    void call(int nargs, int nresults, long long budget, const char* suffix);
    // throws ScriptError, at the definition of the function `function_ref` (a registry
    // reference) that just ran, if it replaced one of self's value arrays by something else
    void check_values(int function_ref);
    static int l_set_angle(lua_State* L);
    static int l_joint_angle(lua_State* L);
    static int l_joint_velocity(lua_State* L);
    static int l_joint_torque(lua_State* L);
    static int l_sensor(lua_State* L);

    lua_State* L_;  // the state's main thread
    std::shared_ptr<LuaControllerClass> cls_;
    std::string label_;  // "controller 'name'", as budget errors say
    // the instance's methods reach it through this box (a userdata), emptied when the instance
    // goes, so a self table kept by Lua code never reaches a controller that is gone. The box
    // has a registry reference of its own: the methods may become garbage (a step can replace
    // self's metatable) while the box must stay writable
    LuaController** box_ = nullptr;
    int box_ref_ = LUA_NOREF;
    // empties the box and lets it go
    void release_box();
    int self_ref_ = LUA_NOREF;      // the instance table passed to step as self
    int snapshot_ref_ = LUA_NOREF;  // what snapshot(self) returned before a reload
    std::uint64_t pushed_version_ = ~std::uint64_t{0};
    std::uint64_t class_version_;
    ControlIO* io_ = nullptr;  // set only while step runs
};

}  // namespace gaitlab::scripting
