// sim:view() and sim:view{port =, host =}: shows a simulation in the host's browser viewer (the
// console makes one on the first call, where the table says); the viewer itself lives above
// scripting/, behind LuaHost::set_view_handler.
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
        LuaHost::ViewRequest request;
        if (!lua_isnoneornil(L, 2)) {
            Fields f(L, 2, 2, {"port", "host"});
            if (f.has("port")) {
                const long long port = f.integer("port", 0);
                if (port < 1 || port > 65535) {
                    f.fail("port", "a port number from 1 to 65535 expected (got " +
                                       std::to_string(port) + ")");
                }
                request.port = static_cast<int>(port);
            }
            if (f.has("host")) {
                request.host = f.string("host", "");
                if (request.host.empty()) f.fail("host", "an address expected (e.g. 127.0.0.1)");
            }
        }
        const std::shared_ptr<Player> player = h.player;
        const std::string url = playback.view(player, h.index, request);
        lua_pushstring(L, url.c_str());
        return 1;
    });
}

}  // namespace gaitlab::scripting
