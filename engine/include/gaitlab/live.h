// Live buffers: fixed-size ring buffers holding the latest samples of selected series of a
// running simulation, for a console or a viewer. The simulation's thread samples every
// `sample_every` ticks and publishes to readers every `refresh_seconds` of wall time; any
// thread may read a snapshot or change the settings at any time.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "gaitlab/series.h"

namespace gaitlab {

class Simulation;
struct Event;

/// What live buffers keep, and how often.
struct LiveOptions {
    std::vector<std::string> series;  ///< kinds or name patterns (SeriesSet); empty: all
    int sample_every = 0;             ///< ticks between samples, >= 1; 0: the control period
    double refresh_seconds = 0.05;    ///< wall time between publications, s, >= 0 (0: each sample)
    int size = 1000;                  ///< samples kept per series, >= 1
};

/// The latest samples, oldest first.
struct LiveSnapshot {
    std::vector<std::string> names;           ///< the series, in the order of `values`
    std::vector<double> time;                 ///< s
    std::vector<std::vector<double>> values;  ///< one vector per name, parallel to `time`
    std::uint64_t version = 0;                ///< publications so far
};

class LiveBuffers {
  public:
    /// Attaches to `sim`, which must outlive the buffers (they detach when destroyed; destroy
    /// them on the simulation's thread). Throws SpecError for bad options or selections.
    LiveBuffers(Simulation& sim, LiveOptions options);
    ~LiveBuffers();
    LiveBuffers(const LiveBuffers&) = delete;
    LiveBuffers& operator=(const LiveBuffers&) = delete;

    /// The series kept (fixed when the buffers were made).
    const std::vector<SeriesInfo>& series() const { return set_.series(); }

    /// Settings; thread-safe, effective from the next sample. Throw SpecError when out of range.
    void set_sample_every(int ticks);
    void set_refresh_seconds(double seconds);
    /// Keeps the newest samples that fit.
    void set_size(int samples);
    /// The checks of size and sample_every, for callers holding a wider number than an int (a
    /// Lua integer): SpecError naming the value as given.
    static void check_size(long long samples);
    static void check_sample_every(long long ticks);
    LiveOptions options() const;

    /// Thread-safe copy of what has been published; `names` empty: every series. Throws
    /// SpecError for an unknown name.
    LiveSnapshot snapshot(const std::vector<std::string>& names = {}) const;
    /// Publications so far (thread-safe, cheap: poll it to know when to redraw).
    std::uint64_t version() const { return version_.load(std::memory_order_acquire); }
    /// Publishes the samples taken since the last publication now (simulation thread).
    void publish();
    /// publish() if samples were taken since the last publication (simulation thread): what a
    /// script reads after sim:run returns is up to the last sample, not to the last refresh.
    void flush() {
        if (pending_count_ > 0) publish();
    }

  private:
    void on_tick(const Simulation& sim);
    void on_event(const Simulation& sim, const Event& e);
    void sample(const Simulation& sim);

    Simulation& sim_;
    SeriesSet set_;
    const size_t width_;  // doubles per sample: time + series
    std::atomic<int> sample_every_;
    std::atomic<std::int64_t> refresh_ns_;
    std::atomic<int> size_;
    std::chrono::steady_clock::time_point next_publish_{};

    // simulation thread only: samples not yet published (at most size_ of them)
    std::vector<double> pending_;
    size_t pending_count_ = 0;
    std::vector<double> row_;

    // shared with readers, under mutex_: a ring of `capacity_` samples
    mutable std::mutex mutex_;
    std::vector<double> ring_;
    size_t capacity_ = 0;
    size_t head_ = 0;     // next slot to write
    size_t count_ = 0;    // samples held
    bool clear_ = false;  // a reset: readers see an empty buffer at the next publication
    std::atomic<std::uint64_t> version_{0};
    int observer_ = 0;
    int listener_ = 0;
};

}  // namespace gaitlab
