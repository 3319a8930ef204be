#include "gaitlab/live.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/event.h"
#include "gaitlab/simulation.h"
#include "gaitlab/suggest.h"
#include "spec/check.h"

namespace gaitlab {

namespace {

void check_every(long long ticks) {
    if (ticks < 1 || ticks > 1'000'000'000) {
        throw SpecError(
            fmt::format("sample_every must be in [1, 1000000000] ticks (got {})", ticks));
    }
}
void check_refresh(double s) {
    if (!(std::isfinite(s) && s >= 0)) {
        throw SpecError(fmt::format("refresh must be a non-negative number of seconds (got {})",
                                    detail::shown(s)));
    }
}
void check_size(long long n) {
    if (n < 1 || n > 10'000'000) {
        throw SpecError(fmt::format("size must be in [1, 10000000] samples (got {})", n));
    }
}
std::int64_t to_ns(double s) {
    return static_cast<std::int64_t>(std::llround(s * 1e9));
}

}  // namespace

void LiveBuffers::check_size(long long samples) {
    gaitlab::check_size(samples);
}
void LiveBuffers::check_sample_every(long long ticks) {
    check_every(ticks);
}

LiveBuffers::LiveBuffers(Simulation& sim, LiveOptions o)
    : sim_(sim),
      set_(sim, o.series),
      width_(set_.size() + 1),
      sample_every_(o.sample_every == 0 ? sim.options().control_every : o.sample_every),
      refresh_ns_(0),
      size_(o.size) {
    check_every(sample_every_.load());
    check_refresh(o.refresh_seconds);
    check_size(o.size);
    refresh_ns_ = to_ns(o.refresh_seconds);
    row_.assign(width_, 0.0);
    capacity_ = static_cast<size_t>(o.size);
    ring_.assign(capacity_ * width_, 0.0);
    observer_ = sim.add_observer([this](const Simulation& s) { on_tick(s); });
    listener_ =
        sim.add_event_listener([this](const Simulation& s, const Event& e) { on_event(s, e); });
}

LiveBuffers::~LiveBuffers() {
    sim_.remove_observer(observer_);
    sim_.remove_event_listener(listener_);
}

void LiveBuffers::set_sample_every(int ticks) {
    check_every(ticks);
    sample_every_ = ticks;
}

void LiveBuffers::set_refresh_seconds(double seconds) {
    check_refresh(seconds);
    refresh_ns_ = to_ns(seconds);
}

void LiveBuffers::set_size(int samples) {
    check_size(samples);
    size_ = samples;
    std::lock_guard<std::mutex> lock(mutex_);
    // the newest samples that fit, oldest first, into a ring of the new size
    const size_t cap = static_cast<size_t>(samples);
    const size_t keep = std::min(count_, cap);
    std::vector<double> ring(cap * width_, 0.0);
    for (size_t i = 0; i < keep; ++i) {
        const size_t from = (head_ + capacity_ - keep + i) % capacity_;
        std::copy_n(ring_.begin() + static_cast<std::ptrdiff_t>(from * width_), width_,
                    ring.begin() + static_cast<std::ptrdiff_t>(i * width_));
    }
    ring_ = std::move(ring);
    capacity_ = cap;
    count_ = keep;
    head_ = keep % cap;
}

LiveOptions LiveBuffers::options() const {
    LiveOptions o;
    for (const SeriesInfo& s : set_.series())
        o.series.push_back(s.name);
    o.sample_every = sample_every_.load();
    o.refresh_seconds = static_cast<double>(refresh_ns_.load()) * 1e-9;
    o.size = size_.load();
    return o;
}

void LiveBuffers::on_tick(const Simulation& sim) {
    set_.tick(sim);
    if (sim.ticks() % sample_every_.load(std::memory_order_relaxed) != 0) return;
    sample(sim);
    const auto now = std::chrono::steady_clock::now();
    if (now >= next_publish_) {
        publish();
        next_publish_ = now + std::chrono::nanoseconds(refresh_ns_.load(std::memory_order_relaxed));
    }
}

void LiveBuffers::sample(const Simulation& sim) {
    row_[0] = sim.time();
    set_.sample(sim, row_.data() + 1);
    // only the newest `size` samples can be seen: pending never holds more
    const size_t limit = static_cast<size_t>(size_.load(std::memory_order_relaxed));
    if (pending_count_ >= limit) {
        pending_.erase(
            pending_.begin(),
            pending_.begin() + static_cast<std::ptrdiff_t>((pending_count_ - limit + 1) * width_));
        pending_count_ = limit - 1;
    }
    pending_.insert(pending_.end(), row_.begin(), row_.end());
    ++pending_count_;
}

void LiveBuffers::on_event(const Simulation& sim, const Event& e) {
    if (e.kind != EventKind::reset) return;
    // time starts again: the old samples would draw backwards
    set_.restart();
    pending_.clear();
    pending_count_ = 0;
    clear_ = true;
    sample(sim);
    publish();
}

void LiveBuffers::publish() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (clear_) {
            count_ = 0;
            head_ = 0;
            clear_ = false;
        }
        for (size_t i = 0; i < pending_count_; ++i) {
            std::copy_n(pending_.begin() + static_cast<std::ptrdiff_t>(i * width_), width_,
                        ring_.begin() + static_cast<std::ptrdiff_t>(head_ * width_));
            head_ = (head_ + 1) % capacity_;
            count_ = std::min(count_ + 1, capacity_);
        }
    }
    pending_.clear();
    pending_count_ = 0;
    version_.fetch_add(1, std::memory_order_release);
}

LiveSnapshot LiveBuffers::snapshot(const std::vector<std::string>& names) const {
    LiveSnapshot s;
    std::vector<size_t> columns;
    if (names.empty()) {
        for (size_t i = 0; i < set_.size(); ++i) {
            s.names.push_back(set_.series()[i].name);
            columns.push_back(i + 1);
        }
    } else {
        std::vector<std::string> all;
        for (const SeriesInfo& i : set_.series())
            all.push_back(i.name);
        for (const std::string& n : names) {
            const int k = set_.find(n);
            if (k < 0) {
                throw SpecError(
                    fmt::format("the live buffers keep no series '{}'{}", n, suggest(n, all)));
            }
            s.names.push_back(n);
            columns.push_back(static_cast<size_t>(k) + 1);
        }
    }
    std::lock_guard<std::mutex> lock(mutex_);
    s.version = version_.load(std::memory_order_acquire);
    s.time.reserve(count_);
    s.values.assign(columns.size(), {});
    for (auto& v : s.values)
        v.reserve(count_);
    for (size_t i = 0; i < count_; ++i) {
        const size_t slot = (head_ + capacity_ - count_ + i) % capacity_;
        const double* row = ring_.data() + slot * width_;
        s.time.push_back(row[0]);
        for (size_t c = 0; c < columns.size(); ++c)
            s.values[c].push_back(row[columns[c]]);
    }
    return s;
}

}  // namespace gaitlab
