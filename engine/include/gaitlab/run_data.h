// Reading run folders (recorder.h writes them): the series list, one or more series over a
// time range, the events, and what run.json says about the run. A last line cut short by a
// killed process is dropped; any other malformed line is an error naming FILE:LINE.
//
// Run folders may come from anyone: the reader never blocks, never reads outside the folder
// and bounds what it holds. The files of the folder must be regular files of the folder itself
// (not links, FIFOs or devices); run.json, series.csv and log.txt are read whole, at most 64 MiB
// each (kMaxInputBytes); data.csv and events.csv are read line by line, of any length, with
// lines of at most 16 MiB (kMaxLineBytes); a run has at most 100000 series (kMaxSeries); the
// configuration files that run.json names must lie inside config/ (config_file).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "gaitlab/event.h"
#include "gaitlab/recorder.h"
#include "gaitlab/series.h"
#include "gaitlab/simulation.h"

namespace gaitlab {

/// One series read back: its description and (time, value) samples.
struct SeriesData {
    SeriesInfo info;
    std::vector<double> time;  ///< s
    std::vector<double> values;
};

/// What run.json says.
struct RunMeta {
    std::string name;
    /// "running" while recording; a folder left "running" belongs to a process that ended
    /// without closing it (killed); "finished" or "failed" (see message) otherwise
    std::string status;
    std::string message;
    /// "failed" because writing the folder failed (a full disk): the data ends at its last
    /// complete row, before the run itself stopped
    bool recording_failed = false;
    std::string started, ended;  ///< UTC, ISO 8601
    long first_tick = 0;         ///< tick of the first row
    /// tick when recording ended (-1: not closed); with recording_failed, the tick of the last
    /// row written in full, where the data ends
    long last_tick = -1;
    int simulation = 1;         ///< which simulation of the script (1-based)
    SimulationOptions options;  ///< dt, control_every, solver_iterations, seed, policy
    int record_every = 0;
    double flush_seconds = 0;
    std::vector<std::string> select;  ///< the series selection
    std::string script;               ///< config-relative path of the script ("" if none)
    std::vector<std::string> args;
    std::uint64_t script_seed = 0;
    std::string started_by = "simulation";  ///< "simulation" or "record" (see RunContext)
    std::vector<ConfigFile> files;          ///< without content (read config/PATH)
    std::vector<std::pair<std::string, std::string>> provenance;
    RunProcess process;  ///< the process that wrote the folder (pid 0: not recorded)
};

/// The longest line the reader takes from data.csv, series.csv and events.csv.
inline constexpr size_t kMaxLineBytes = size_t{16} << 20;
/// The most series a run folder may list.
inline constexpr size_t kMaxSeries = 100000;

/// Whether a process that wrote a run folder still runs.
enum class Liveness {
    gone,     ///< no process with its pid and start time runs on this host since this boot
    alive,    ///< it runs
    unknown,  ///< it ran on another host, or run.json names no process
};
Liveness liveness(const RunProcess& process);

/// File names for the series `names` (`gaitlab data --split`, run:export{dir=}), in order:
/// NAME.csv, where every '/', '\\', control character or byte that is not UTF-8 becomes '_', a
/// leading '.' or '-' gets a '_' before it, long names are cut (255 bytes with ".csv"), and
/// names that would end up alike get "~2", "~3", ... So no name leaves the folder or makes a
/// hidden file, an option-like file or two series share a file.
std::vector<std::string> series_file_names(const std::vector<std::string>& names);

class RunData {
  public:
    /// Opens a run folder. A missing folder, or one that lacks run.json, series.csv or
    /// data.csv, throws IoError saying what it lacks; malformed content throws FormatError.
    explicit RunData(std::string dir);

    /// Reads and checks run.json alone; throws IoError or FormatError (FILE:LINE: what).
    static RunMeta read_meta(const std::string& path);

    const std::string& dir() const { return dir_; }
    const RunMeta& meta() const { return meta_; }
    /// How the run ended, in words: "finished", "failed: MESSAGE", "interrupted by SIGTERM";
    /// while run.json says "running": "running (still being written by process N)" if that
    /// process runs, "incomplete (the process ended without closing it)" if it is gone.
    std::string state() const;
    /// The path of config/PATH in this run folder, PATH as run.json or events.csv name it;
    /// throws FormatError if it leads out of config/ ("..", an absolute path, a link).
    std::string config_file(const std::string& path) const;
    const std::vector<SeriesInfo>& series() const { return series_; }
    std::vector<std::string> names() const;

    /// The series called `name`; throws SpecError suggesting the closest names.
    const SeriesInfo& find(std::string_view name) const;
    /// The one series of `kind` with quantity `value` and `joint` (0: none), from `source`
    /// when given; throws SpecError if none or several match (naming them).
    const SeriesInfo& find(SeriesKind kind, std::string_view value, int joint,
                           std::string_view source = {}) const;
    /// Names selected by `patterns` (names, kinds or '*' patterns), in file order, each once;
    /// a pattern that selects nothing throws SpecError with suggestions.
    std::vector<std::string> select(const std::vector<std::string>& patterns) const;

    /// The named series, rows with from <= time <= to; throws SpecError if `from` or `to` is
    /// NaN.
    SeriesData get(std::string_view name, double from = -kInf, double to = kInf) const;
    /// Several at once (one pass over the file).
    std::vector<SeriesData> get(const std::vector<std::string>& names, double from = -kInf,
                                double to = kInf) const;
    /// The time column of every complete row, s.
    std::vector<double> times() const;
    /// Complete rows in data.csv (reads the file).
    long rows() const;
    /// Whether data.csv ends in a partly written line (dropped by every read).
    bool truncated() const;
    /// events.csv (empty if the file is missing).
    std::vector<Event> events() const;
    /// log.txt ("" if missing).
    std::string log() const;

    /// Throws IoError naming the file if writing `path` would replace one of this run's own
    /// files (run.json, series.csv, data.csv, events.csv, log.txt) or write into its config/,
    /// whatever link or alias leads there. Every export and plot of the run checks its files.
    void refuse_own(const std::string& path) const;

    /// Writes "time,<names...>" and the rows in [from, to] as CSV; throws IoError (also for a
    /// path refuse_own refuses).
    void write_csv(const std::string& path, const std::vector<std::string>& names,
                   double from = -kInf, double to = kInf) const;

    /// Writes each series into a file of its own in `dir` (made if missing), named by
    /// series_file_names, with "time,<name>" and the rows in [from, to]; returns the files in
    /// the order of `names`. Throws IoError (also, before writing anything, for a file
    /// refuse_own refuses).
    std::vector<std::string> write_split(const std::string& dir,
                                         const std::vector<std::string>& names, double from = -kInf,
                                         double to = kInf) const;

    static constexpr double kInf = std::numeric_limits<double>::infinity();

  private:
    std::string dir_;
    RunMeta meta_;
    std::vector<SeriesInfo> series_;
    std::unordered_map<std::string, size_t> index_;  // name -> its first series
};

/// How a replay compares with the run it replays.
struct Comparison {
    bool identical = false;
    long rows = 0;           ///< rows compared
    size_t series = 0;       ///< series per row
    std::string difference;  ///< the first difference ("" if identical)
};

/// Compares the data of two runs bit for bit: the same series, and every complete row of
/// `run` equal to the same row of `replay` (which may go on where `run` was cut short, if
/// `run` did not finish).
Comparison compare(const RunData& run, const RunData& replay);

}  // namespace gaitlab
