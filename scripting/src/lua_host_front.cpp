// What LuaHost gives a front end that drives simulations from outside the script (a viewer):
// the players of new simulations, the runner of sim:run and sim:step, the handlers of sim:view()
// and gaitlab.optimize{}, the interrupt's message.
#include "gaitlab/scripting/lua_host.h"

#include "guard.h"
#include "playback.h"

namespace gaitlab::scripting {

void LuaHost::on_player(std::function<void(const std::shared_ptr<Player>&, int)> fn) {
    Playback::of(L_).on_player.push_back(std::move(fn));
}

void LuaHost::set_runner(Runner fn) {
    Playback::of(L_).runner = std::move(fn);
}

void LuaHost::set_view_handler(ViewHandler fn) {
    Playback::of(L_).view = std::move(fn);
}

void LuaHost::set_optimize_handler(OptimizeHandler fn) {
    Playback::of(L_).optimize = std::move(fn);
}

std::string LuaHost::interrupt_message() const {
    return guard_->interrupted() != 0 ? guard_->interrupt_message() : std::string();
}

}  // namespace gaitlab::scripting
