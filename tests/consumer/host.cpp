// The Lua host from an installed gaitlab: a script builds and runs a snake, as `gaitlab run` would.
#include <cstdio>

#include "gaitlab/scripting/lua_host.h"

int main() {
    try {
        gaitlab::scripting::LuaHost host;
        host.run_string(R"(
            local robot = gaitlab.robot.chain{ name = "snake", modules = 8 }
            local world = gaitlab.world{ floor = { friction = 0.8 } }
            world:add(robot)
            robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = -120 })
            local sim = gaitlab.simulation{ world = world }
            sim:run(5)
            print(string.format("lua moved x %.3f m", robot:displacement().x))
        )",
                        "=host");
        host.run_string("error('on purpose')", "=host");  // errors come back as ScriptError
        std::printf("no error\n");
        return 1;
    } catch (const gaitlab::scripting::ScriptError& e) {
        std::printf("error: %s\n", e.what());
        return 0;
    }
}
