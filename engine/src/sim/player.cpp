#include "gaitlab/player.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/simulation.h"
#include "spec/check.h"

namespace gaitlab {

namespace {

// the measured real-time factor covers at least this much wall time, s
constexpr double kMeasureWindow = 0.5;

}  // namespace

double steady_seconds() {
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
}

Player::Player(std::shared_ptr<Simulation> sim) : sim_(std::move(sim)) {
    // a reset gives the simulation a fresh start: it may play again after a failure
    listener_ = sim_->add_event_listener([this](const Simulation&, const Event& e) {
        if (e.kind == EventKind::reset) failure_.clear();
    });
    last_ticks_ = sim_->ticks();
}

Player::~Player() {
    sim_->remove_event_listener(listener_);
}

void Player::play(double now) {
    if (playing_) return;
    playing_ = true;
    rebase_pending_ = false;
    rebase(now);
    window_wall_ = now;
    window_time_ = sim_->time();
    measured_ = std::numeric_limits<double>::quiet_NaN();
}

void Player::set_speed(double speed) {
    if (!(speed > 0)) {
        throw SpecError(
            fmt::format("speed must be a real-time factor > 0 (inf: as fast as possible), got {}",
                        detail::shown(speed)));
    }
    speed_ = speed;
    rebase_pending_ = true;
}

void Player::set_delay(double seconds) {
    if (!(seconds >= 0 && seconds <= kMaxPlayDelay)) {
        throw SpecError(fmt::format("delay must be in [0, {:g}] s, got {}", kMaxPlayDelay,
                                    detail::shown(seconds)));
    }
    delay_ = seconds;
    rebase_pending_ = true;
}

void Player::fail(std::string why) {
    playing_ = false;
    failure_ = std::move(why);
}

double Player::period() const {
    return sim_->options().dt / speed_ + delay_;  // dt / inf = 0
}

long Player::due(double now) const {
    const double period = this->period();
    if (period <= 0) return kMaxTicks;
    // a hair of slack: 0.5 s at 1 ms per tick is 500 ticks, not 499.99999
    const double n = std::floor((now - base_wall_) / period + 1e-9);
    if (!(n < static_cast<double>(kMaxTicks - base_ticks_))) return kMaxTicks;
    return base_ticks_ + static_cast<long>(std::max(n, 0.0));
}

void Player::rebase(double now) {
    base_wall_ = now;
    base_ticks_ = last_ticks_ = sim_->ticks();
}

void Player::measure(double now) {
    if (now - window_wall_ < kMeasureWindow) return;
    measured_ = (sim_->time() - window_time_) / (now - window_wall_);
    window_wall_ = now;
    window_time_ = sim_->time();
}

long Player::advance(const WallClock& clock, double deadline) {
    if (!playing_) return 0;
    Simulation& sim = *sim_;
    double now = clock();
    if (sim.ticks() != last_ticks_) {
        // stepped, run or reset by someone else: pace and measure from here
        rebase(now);
        window_wall_ = now;
        window_time_ = sim.time();
    } else if (rebase_pending_) {
        rebase(now);
    }
    rebase_pending_ = false;
    long run = 0;
    while (sim.ticks() < due(now) && (run == 0 || now < deadline)) {
        try {
            sim.step(1);
        } catch (...) {
            playing_ = false;
            last_ticks_ = sim.ticks();
            throw;
        }
        ++run;
        now = clock();
        if (sim.paused()) {  // a controller failed under the pause policy
            playing_ = false;
            break;
        }
    }
    last_ticks_ = sim.ticks();
    // too far behind to catch up (too slow, or not called for a while): pace from here
    const double period = this->period();
    if (playing_ && period > 0 &&
        static_cast<double>(due(now) - sim.ticks()) * period > kMaxPlayLag) {
        rebase(now);
    }
    measure(now);
    return run;
}

double Player::wait(double now) const {
    if (!playing_) return kInf;
    const double period = this->period();
    if (period <= 0 || rebase_pending_ || sim_->ticks() != last_ticks_) return 0;
    const double next = base_wall_ + static_cast<double>(sim_->ticks() - base_ticks_ + 1) * period;
    return std::max(0.0, next - now);
}

}  // namespace gaitlab
