#include "playback.h"

#include <algorithm>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "gaitlab/controller.h"
#include "gaitlab/simulation.h"
#include "guard.h"
#include "hot_reload.h"
#include "lua_util.h"
#include "recording.h"

namespace gaitlab::scripting {

namespace {

constexpr const char* kPlaybackKey = "gaitlab.playback";
constexpr const char* kPlaybackType = "gaitlab.Playback";
constexpr double kInf = std::numeric_limits<double>::infinity();

// a progress line appears once a run lasts this long, and changes at most this often (wall s)
constexpr double kProgressFirst = 0.5;
constexpr double kProgressEvery = 0.25;
// the clock is read every this many ticks of a run with a progress hook
constexpr long kProgressTicks = 64;

// the first controller of `sim` that failed, or null
const Controller* failed_controller(const Simulation& sim, std::string* label) {
    for (int d = 0; d < sim.drive_count(); ++d) {
        if (sim.controller(d).failed()) {
            if (label) *label = sim.drive_label(d);
            return &sim.controller(d);
        }
    }
    return nullptr;
}

// the first line of a message (a traceback may follow)
std::string first_line(const std::string& s) {
    return s.substr(0, s.find('\n'));
}

}  // namespace

Playback& Playback::of(lua_State* L) {
    lua_getfield(L, LUA_REGISTRYINDEX, kPlaybackKey);
    auto* p = static_cast<Playback*>(lua_touserdata(L, -1));
    lua_pop(L, 1);
    return *p;
}

void Playback::install(lua_State* L) {
    register_type<Playback>(L, kPlaybackType, nullptr);
    new_object<Playback>(L, kPlaybackType, Playback{});
    lua_setfield(L, LUA_REGISTRYINDEX, kPlaybackKey);
}

void Playback::play(SimulationHandle& h) {
    Player& p = *h.player;
    const Simulation& sim = p.simulation();
    if (!p.failure().empty()) {
        throw Error(fmt::format("cannot play simulation {}: it {}; call sim:reset() first", h.index,
                                p.failure()));
    }
    // under "stop" a failed controller stopped the simulation: it plays again once a fix of its
    // file reloaded (which revives it) or after a reset
    std::string label;
    const Controller* c = failed_controller(sim, &label);
    if (c && sim.options().on_controller_error == ControllerErrorPolicy::stop) {
        throw Error(fmt::format(
            "cannot play simulation {}: controller '{}' failed ({}); save a fix to its file (it "
            "reloads) or call sim:reset()",
            h.index, label, first_line(c->failure())));
    }
    p.play(clock());
    const bool listed = std::any_of(playing_.begin(), playing_.end(),
                                    [&](const Entry& e) { return e.player == h.player; });
    if (!listed) playing_.push_back({h.player, h.index});
}

int Playback::playing() const {
    return static_cast<int>(std::count_if(playing_.begin(), playing_.end(),
                                          [](const Entry& e) { return e.player->playing(); }));
}

void Playback::pause_all(lua_State* L, const std::string& why) {
    for (const Entry& e : playing_) {
        if (!e.player->playing()) continue;
        e.player->pause();
        if (why.empty()) continue;
        report(L, fmt::format("simulation {} paused at t = {:.3f} s: {}", e.index,
                              e.player->simulation().time(), why));
    }
}

double Playback::pump(lua_State* L) {
    if (pumping_) return kInf;  // called from a callback of its own pump: nothing to add
    pumping_ = true;
    struct Leave {
        bool& flag;
        ~Leave() { flag = false; }
    } leave{pumping_};
    Reloader& reloader = Reloader::of(L);
    std::optional<std::string> failed;  // reported after the handler (see lua_util.h)
    try {
        // saved controller files reload at once, whether or not a control tick is due
        reloader.poll(L);
    } catch (const std::exception& e) {
        failed = e.what();
    }
    if (failed) report(L, "reload failed: " + *failed);
    playing_.erase(std::remove_if(playing_.begin(), playing_.end(),
                                  [](const Entry& e) { return !e.player->playing(); }),
                   playing_.end());
    // with nothing playing, controller files are still checked at the reload interval: a fix
    // saved while a failed simulation waits reloads (and says so) at once, not at the next
    // command typed
    const double reload_wait = reloader.watching() ? std::max(reloader.interval(), 0.05) : kInf;
    if (playing_.empty()) return reload_wait;
    const Guard& guard = Guard::of(L);
    if (guard.interrupted() != 0) {
        pause_all(L, guard.interrupt_message());
        return kInf;
    }
    // each in turn goes first, so a slow simulation cannot starve the others; a copy, since
    // controllers may start or stop simulations while they are stepped
    std::vector<Entry> order = playing_;
    const size_t first = next_ % order.size();
    std::rotate(order.begin(), order.begin() + static_cast<long>(first), order.end());
    next_ = first + 1;
    const double deadline = clock() + slice;
    for (const Entry& e : order) {
        Player& p = *e.player;
        Simulation& sim = p.simulation();
        if (!p.playing()) continue;
        bool threw = false;
        std::string error;     // what stopped it: the message, a traceback on the next lines
        std::string headline;  // its first line
        try {
            p.advance(clock, deadline);
        } catch (const std::exception& ex) {
            threw = true;
            error = ex.what();
            headline = first_line(error);
            const auto* se = dynamic_cast<const ScriptError*>(&ex);
            if (se && !se->traceback().empty()) error += "\n" + se->traceback();
        }
        if (!threw) {
            if (!p.playing()) {
                // the controller's failure was reported as it happened
                report(L, fmt::format("simulation {} paused at t = {:.3f} s (a controller failed)",
                                      e.index, sim.time()));
            }
            continue;
        }
        if (guard.interrupted() != 0) {
            report(L, fmt::format("simulation {} paused at t = {:.3f} s: {}", e.index, sim.time(),
                                  guard.interrupt_message()));
            pause_all(L, guard.interrupt_message());
            return kInf;
        }
        std::string label;
        if (failed_controller(sim, &label)) {
            report(L, fmt::format("simulation {} paused at t = {:.3f} s: controller '{}' "
                                  "failed: {}",
                                  e.index, sim.time(), label, error));
        } else {
            p.fail(fmt::format("failed at t = {:.3f} s ({})", sim.time(), headline));
            report(L, fmt::format("simulation {} failed at t = {:.3f} s and was paused "
                                  "(sim:reset() to play it again): {}",
                                  e.index, sim.time(), error));
        }
    }
    double wait = kInf;
    const double now = clock();
    for (const Entry& e : playing_)
        wait = std::min(wait, e.player->wait(now));
    // controller files are checked at least this often
    return std::min(wait, reload_wait);
}

void Playback::before_output() const {
    if (active_ && active_->shown_) active_->hide();
}

ProgressScope::ProgressScope(lua_State* L, Simulation& sim, double end_time)
    : playback_(Playback::of(L)), sim_(sim) {
    if (!playback_.progress) return;
    outer_ = playback_.active_;
    playback_.active_ = this;
    active_ = true;
    start_wall_ = playback_.clock();
    next_ = start_wall_ + kProgressFirst;
    last_.start = sim.time();
    last_.end = end_time;
    observer_ = sim.add_observer([this](const Simulation& s) {
        if (s.ticks() % kProgressTicks != 0) return;
        const double now = playback_.clock();
        if (now < next_) return;
        next_ = now + kProgressEvery;
        last_.time = s.time();
        last_.wall = now - start_wall_;
        last_.done = false;
        shown_ = true;
        playback_.progress(last_);
    });
}

ProgressScope::~ProgressScope() {
    if (!active_) return;
    sim_.remove_observer(observer_);
    if (shown_) hide();
    playback_.active_ = outer_;
}

void ProgressScope::hide() {
    shown_ = false;
    last_.done = true;
    last_.time = sim_.time();
    last_.wall = playback_.clock() - start_wall_;
    playback_.progress(last_);
}

}  // namespace gaitlab::scripting
