#include "gaitlab/replay.h"

#include <fmt/format.h>

#include "gaitlab/controller.h"
#include "gaitlab/simulation.h"

namespace gaitlab {

EventReplay::EventReplay(Simulation& sim, std::vector<Event> events, Apply apply_other,
                         long stop_tick)
    : sim_(sim),
      events_(std::move(events)),
      apply_other_(std::move(apply_other)),
      stop_tick_(stop_tick) {
    hook_ = sim_.add_pre_tick([this](Simulation& s) {
        apply_due();
        // past the last recorded row, once every recorded event has been seen
        if (stop_tick_ >= 0 && next_ >= events_.size() && s.ticks() >= stop_tick_) {
            if (!ended_ && on_end_) on_end_();
            ended_ = true;
            throw ReplayEnd(
                fmt::format("the replay reached the end of the recording (tick {})", stop_tick_));
        }
    });
    listener_ = sim_.add_event_listener([this](const Simulation&, const Event& e) { on_event(e); });
}

EventReplay::~EventReplay() {
    detach();
}

void EventReplay::detach() {
    if (!attached_) return;
    attached_ = false;
    sim_.remove_pre_tick(hook_);
    sim_.remove_event_listener(listener_);
}

std::string EventReplay::describe(const Event& e) {
    switch (e.kind) {
        case EventKind::param:
            return fmt::format("{} = {} ({}, tick {})", e.name, e.value, to_string(e.origin),
                               e.tick);
        case EventKind::reset:
            return fmt::format("a reset ({}, tick {})", to_string(e.origin), e.tick);
        default:
            return fmt::format("{} '{}' {} ({}, tick {})", to_string(e.kind), e.name, e.value,
                               to_string(e.origin), e.tick);
    }
}

void EventReplay::diverge(std::string message) {
    if (divergence_.empty()) divergence_ = std::move(message);
}

void EventReplay::apply_due() {
    while (divergence_.empty() && next_ < events_.size()) {
        const Event e = events_[next_];
        // the script's own changes come from the script; the others are due at their tick
        if (e.origin == Origin::script || e.tick != sim_.ticks()) return;
        const size_t before = next_;
        applying_ = true;
        try {
            switch (e.kind) {
                case EventKind::param: {
                    bool found = false;
                    for (int d = 0; d < sim_.drive_count() && !found; ++d) {
                        Controller& c = sim_.controller(d);
                        const std::string& label = sim_.drive_label(d);
                        if (e.name.size() <= label.size() + 1 ||
                            e.name.compare(0, label.size(), label) != 0 ||
                            e.name[label.size()] != '.')
                            continue;
                        const int p = c.find_param(e.name.substr(label.size() + 1));
                        if (p < 0) continue;
                        found = true;
                        c.set_param(p, e.value, e.origin);
                    }
                    if (!found) {
                        diverge(fmt::format("cannot replay {}: the replay has no such parameter",
                                            describe(e)));
                    }
                    break;
                }
                case EventKind::reset:
                    sim_.reset(e.origin);
                    break;
                case EventKind::reload:
                    if (!apply_other_) {
                        diverge(fmt::format("cannot replay {}: reloads need the script host",
                                            describe(e)));
                    } else {
                        apply_other_(sim_, e);
                    }
                    break;
                case EventKind::sensor: {
                    const int i = sim_.find_sensor(e.name);
                    if (i < 0) {
                        diverge(fmt::format("cannot replay {}: the replay has no such sensor",
                                            describe(e)));
                    } else {
                        sim_.set_sensor_enabled(i, e.value != 0, e.origin);
                    }
                    break;
                }
                case EventKind::drive:
                    diverge(
                        fmt::format("cannot replay {}: only parameter changes, sensor switches, "
                                    "reloads and resets made outside the script can be replayed",
                                    describe(e)));
                    break;
            }
        } catch (const std::exception& ex) {
            applying_ = false;
            diverge(fmt::format("cannot replay {}: {}", describe(e), ex.what()));
            return;
        }
        applying_ = false;
        if (divergence_.empty() && next_ == before) {
            diverge(fmt::format("replaying {} changed nothing", describe(e)));
        }
    }
}

void EventReplay::on_event(const Event& e) {
    if (!divergence_.empty()) return;
    if (next_ >= events_.size()) {
        diverge(fmt::format("the replay made a change the run did not record: {}", describe(e)));
        return;
    }
    const Event& want = events_[next_];
    const bool same = e.kind == want.kind && e.name == want.name && e.origin == want.origin &&
                      e.tick == want.tick &&
                      (e.value == want.value || (e.value != e.value && want.value != want.value));
    if (!same) {
        diverge(
            fmt::format("the replay made {} where the run made {}", describe(e), describe(want)));
        return;
    }
    ++next_;
    if (applying_) ++applied_;
}

}  // namespace gaitlab
