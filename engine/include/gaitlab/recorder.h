// The recorder: samples the series of a simulation (series.h) every `record_every` ticks and
// writes a run folder (docs/data.md):
//
//   run.json     what ran: options, seed, recording settings, configuration files, status,
//                provenance (gaitlab version, compiler, CPU, date)
//   series.csv   name,kind,source,value,joint,body,unit: one line per recorded series
//   data.csv     time first, then one column per series; header = series names
//   events.csv   tick,time,origin,kind,name,value,detail: every change made while recording
//   log.txt      the run's messages (and what the script printed)
//   config/      a copy of the configuration that ran (script, controller files, ...)
//
// data.csv, events.csv and log.txt grow by appending, written to the operating system every
// `flush_seconds` of wall time: a process killed with SIGKILL leaves a readable folder that
// lacks at most the last flush period (and may end in a partly written line, which readers
// drop). run.json and series.csv are replaced atomically. run.json names the process that
// writes the folder (RunProcess), and a recorder holds a lock on the folder while it is open,
// so no second recorder (in this process or another) can empty a folder being written.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gaitlab/series.h"

namespace gaitlab {

class Simulation;
struct Event;

namespace formats {
class AppendFile;
}

/// How a simulation is recorded.
struct RecordOptions {
    /// The run folder: created if missing; an existing one must be empty or an earlier run
    /// folder (which is replaced) that no recorder has open.
    std::string dir;
    int record_every = 0;             ///< ticks between rows, >= 1; 0: the control period
    double flush_seconds = 2;         ///< wall time between writes to disk, s, >= 0
    std::vector<std::string> series;  ///< kinds or name patterns (SeriesSet); empty: all
};

/// Checks ranges; throws SpecError.
void validate(const RecordOptions& options);

/// A file of the configuration that ran, copied into the run folder's config/.
struct ConfigFile {
    /// "script", "controller" (a controller file, in the order they were loaded), "reload" (a
    /// new version of one); the XML parts will add "master", "robot", "actuation", "environment"
    std::string role;
    std::string path;           ///< relative to config/, e.g. "controllers/my_sine.lua"
    std::string origin;         ///< where it was read from
    std::string content;        ///< what was read (and ran)
    std::string of;             ///< reload: the path of the controller file it is a version of
    std::uint64_t version = 0;  ///< reload: the class version it became
    /// the FNV-1a 64 hash of content, "fnv1a64:" and 16 hex digits: the recorder computes it
    /// for run.json; read back, "" for folders written before gaitlab recorded it
    std::string hash;
};

/// What ran besides the simulation: run.json keeps it for replay and provenance.
struct RunContext {
    std::string script;             ///< config-relative path of the script that ran ("" if none)
    std::vector<std::string> args;  ///< the script's arguments
    std::uint64_t script_seed = 0;  ///< the seed of the script's random numbers (--seed)
    int simulation = 1;             ///< which simulation (1-based, in creation order) this is
    /// what started the recording: "simulation" (when it was created) or "record" (a later
    /// call of sim:record); a replay starts it at the same point
    std::string started_by = "simulation";
    std::vector<ConfigFile> files;
    /// extra provenance, e.g. {"lua", "Lua 5.4.4"}, {"command", "gaitlab run ..."}
    std::vector<std::pair<std::string, std::string>> provenance;
};

/// The process that writes a run folder, as run.json records it: enough to tell later whether
/// that very process still runs (a pid alone may have been reused).
struct RunProcess {
    long pid = 0;                  ///< 0: not recorded (folders from before it was)
    std::string host;              ///< the host name
    std::string boot_id;           ///< the kernel's boot id (/proc/sys/kernel/random/boot_id)
    std::uint64_t start_time = 0;  ///< when it started, clock ticks after boot (/proc/PID/stat)
};

/// This process.
RunProcess this_process();

/// Makes and returns "<root>/<name>-<YYYYmmdd-HHMMSS>" (local time), with "-2", "-3", ... when
/// that exists (made here, so concurrent runs never get the same folder, and the folder
/// returned is always a new one); throws IoError if none can be made.
std::string default_run_dir(const std::string& root, const std::string& name);

/// Provenance of this build and machine: gaitlab, bullet, compiler, cpu, cores, os, host, date.
std::vector<std::pair<std::string, std::string>> provenance();

class Recorder {
  public:
    /// Locks and prepares the folder, writes run.json, series.csv and the configuration,
    /// records the state now as the first row and attaches to `sim`, which must outlive the
    /// recorder or see it closed first. Throws IoError (the folder, or a folder that another
    /// recorder has open) or SpecError (options, selection).
    Recorder(Simulation& sim, RecordOptions options, RunContext context = {});
    /// Closes as "finished" if still open (errors are dropped: call close() to see them).
    ~Recorder();
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    const std::string& dir() const { return options_.dir; }
    const RecordOptions& options() const { return options_; }
    const SeriesSet& series() const { return set_; }
    /// Rows recorded so far (written or buffered).
    long rows() const { return rows_; }
    bool closed() const { return closed_; }

    /// Writes everything buffered (data, events, log) now. A write that fails stops the
    /// recording, as every failed write does (run.json says "failed", recording_failed), and
    /// throws IoError.
    void flush();
    /// Adds a line to log.txt (written with the next flush).
    void log(std::string_view line);
    /// Copies a file into config/ now, atomically (e.g. a reloaded controller's new code);
    /// throws IoError.
    void add_config_file(ConfigFile file);

    /// Stops recording: detaches, flushes, marks run.json with `status` ("finished", "failed"
    /// with `message` saying why, "interrupted" with `message` naming the signal) and unlocks
    /// the folder. Safe to call again; throws IoError if the last writes fail.
    void close(const std::string& status = "finished", const std::string& message = {});

  private:
    void on_tick(const Simulation& sim);
    void on_event(const Simulation& sim, const Event& e);
    void write_row(const Simulation& sim);
    void maybe_flush();
    // writes the buffers; throws IoError, the recording still open (flush() stops it)
    void write_buffers();
    // writes data_buf_, counting the rows that reach data.csv in full, also when it fails
    void write_data();
    /// throws IoError (and sets folder_gone_) if options_.dir is no longer the folder recorded
    void check_folder();
    // a write failed: stop recording, keep what was written, say so in the exception
    [[noreturn]] void fail(const std::exception& e);
    // write_failed: the recording stopped because a write failed (run.json says so)
    void write_meta(const std::string& status, const std::string& message,
                    bool write_failed = false);
    void unlock();

    Simulation* sim_;
    RecordOptions options_;
    RunContext context_;
    SeriesSet set_;
    std::vector<double> values_;
    std::unique_ptr<formats::AppendFile> data_, events_, log_;
    int lock_ = -1;             // the folder, opened and locked (flock) while recording
    bool folder_gone_ = false;  // the folder was moved or deleted while recording (flush)
    std::string data_buf_, events_buf_, log_buf_;
    long rows_ = 0;
    // the rows data.csv holds in full and the tick of the last of them: what run.json counts
    long rows_written_ = 0;
    long last_written_tick_ = 0;
    std::uint64_t data_bytes_ = 0;  // bytes written to data.csv
    struct BufferedRow {
        size_t end;  // offset after the row's '\n' in data_buf_
        long tick;
    };
    std::vector<BufferedRow> buffered_;  // the rows in data_buf_, in order
    long first_tick_ = 0;
    bool closed_ = false;
    int observer_ = 0;
    int listener_ = 0;
    std::string started_;
    RunProcess process_;
    std::chrono::steady_clock::time_point next_flush_;
    std::chrono::steady_clock::duration flush_period_;
};

}  // namespace gaitlab
