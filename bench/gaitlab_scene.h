// The benchmark scenario through gaitlab: with the C++ API, and through the Lua host with either
// the built-in sine or the Lua controller of examples/controllers/my_sine.lua.
#pragma once

#include <memory>
#include <string>

#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/simulation.h"
#include "raw_bullet_loop.h"
#include "scenario.h"

namespace gaitlab_bench {

/// The snake of `scenario` with its sine drives (pitch group, and yaw group for pitch-yaw).
gaitlab::WorldSpec make_world(const Scenario& scenario);
gaitlab::SimulationOptions make_options(const Scenario& scenario);

/// The same scene built by a Lua script in a LuaHost, stepped with sim:step(n).
class LuaScene {
  public:
    /// `controller_file` empty: gaitlab.controllers.sine; otherwise a Lua controller file with
    /// the parameters amplitude, frequency and phase (examples/controllers/my_sine.lua).
    LuaScene(const Scenario& scenario, const std::string& controller_file);
    void step(long ticks);
    Vec displacement();

  private:
    gaitlab::scripting::LuaHost host_;
};

/// examples/controllers/my_sine.lua in the source tree this program was built from.
std::string default_lua_controller();

}  // namespace gaitlab_bench
