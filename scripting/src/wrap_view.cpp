// sim:view(): shows a simulation in the host's browser viewer (the console makes one on the
// first call); the viewer itself lives above scripting/, behind LuaHost::set_view_handler.
#include "lua_util.h"
#include "playback.h"
#include "recording.h"
#include "wrap.h"

namespace gaitlab::scripting {

int simulation_view(lua_State* L) {
    return protect(L, [&] {
        SimulationHandle& h = check_object<SimulationHandle>(L, 1, kSimulationType);
        const Playback& playback = Playback::of(L);
        if (!playback.view) {
            throw Error(
                "sim:view(): no viewer here: run the script with gaitlab run FILE --view, or "
                "call it in the console (gaitlab, gaitlab -i FILE.lua)");
        }
        const std::shared_ptr<Player> player = h.player;
        const std::string url = playback.view(player, h.index);
        lua_pushstring(L, url.c_str());
        return 1;
    });
}

}  // namespace gaitlab::scripting
