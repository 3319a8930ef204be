// The binding files and the type names of the userdata they create. gaitlab_module.cpp calls
// every open_* function: that list is the map of the Lua API.
#pragma once

#include <lua.hpp>

#include <memory>

namespace gaitlab {
class Controller;
}
#include "gaitlab/module.h"
#include "guard.h"

namespace gaitlab::scripting {

/// Opens gaitlab in L's state (once: again, it pushes the same table) and pushes its table:
/// lua_CFunction-like, raises Lua errors. luaopen_gaitlab is this for a LuaHost's state.
int open_gaitlab(lua_State* L, StateOwner owner);

struct RobotBinding;
struct WorldBinding;

inline constexpr const char* kRobotType = "gaitlab.Robot";
inline constexpr const char* kGroupType = "gaitlab.Group";
inline constexpr const char* kWorldType = "gaitlab.World";
inline constexpr const char* kSimulationType = "gaitlab.Simulation";
inline constexpr const char* kControllerType = "gaitlab.Controller";
inline constexpr const char* kControllerClassType = "gaitlab.ControllerClass";
inline constexpr const char* kActuationType = "gaitlab.Actuation";
inline constexpr const char* kSensorType = "gaitlab.Sensor";
inline constexpr const char* kModuleType = "gaitlab.Module";
inline constexpr const char* kRunType = "gaitlab.Run";
inline constexpr const char* kLiveType = "gaitlab.Live";

// each open_* adds its functions to the gaitlab table on top of the stack
void open_robot(lua_State* L);
void open_world(lua_State* L);
void open_simulation(lua_State* L);
void open_controller(lua_State* L);
/// Pushes a gaitlab.controller table: callable (gaitlab.controller{...}), with load, reload,
/// templates, template and write_template. For a sandbox, `sandbox_folder` is the folder of
/// its file: loads stay sandboxed and writes stay inside that folder; nullptr for scripts.
void push_controller_api(lua_State* L, const char* sandbox_folder);
void open_actuation(lua_State* L);
void open_sensor(lua_State* L);

// robot:sensor{...} / robot:sensor(name) and robot:sensors() (wrap_sensor.cpp), methods of
// the robot handle
int robot_sensor(lua_State* L);
int robot_sensors(lua_State* L);
void open_module(lua_State* L);
void open_data(lua_State* L);
/// gaitlab.optimize{...} (wrap_optimize.cpp): runs an optimization through the host's handler.
void open_optimize(lua_State* L);

/// sim:live{...} (wrap_data.cpp): live buffers of a simulation.
int live_new(lua_State* L);
/// sim:view() (wrap_view.cpp): shows the simulation in the host's viewer; returns its address.
int simulation_view(lua_State* L);

bool is_robot(lua_State* L, int index);
std::shared_ptr<RobotBinding> to_robot(lua_State* L, int index);
std::shared_ptr<WorldBinding> to_world(lua_State* L, int index);
/// Pushes the robot's handle: the one it has while that lives, else a new one (push_canonical).
void push_robot(lua_State* L, std::shared_ptr<RobotBinding> robot);
/// Pushes the world's handle: the one it has while that lives, else a new one.
void push_world(lua_State* L, std::shared_ptr<WorldBinding> world);
/// Pushes the controller's handle: the one it has while that lives, else a new one; `attached`
/// if a group already uses it.
void push_controller(lua_State* L, std::shared_ptr<Controller> controller, bool attached);
/// The module type at `index`: a gaitlab.Module, or the name of one in gaitlab.modules. Throws
/// Error ("unknown module type 'x'; did you mean ...") otherwise.
ModuleDef to_module(lua_State* L, int index);

}  // namespace gaitlab::scripting
