// Reading run folders (recorder.h writes them): the series list, one or more series over a
// time range, the events, and what run.json says about the run. A last line cut short by a
// killed process is dropped; any other malformed line is an error naming FILE:LINE.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
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
    std::string started, ended;  ///< UTC, ISO 8601
    long first_tick = 0;         ///< tick of the first row
    long last_tick = -1;         ///< tick when recording ended (-1: not closed)
    int simulation = 1;          ///< which simulation of the script (1-based)
    SimulationOptions options;   ///< dt, control_every, solver_iterations, seed, policy
    int record_every = 0;
    double flush_seconds = 0;
    std::vector<std::string> select;  ///< the series selection
    std::string script;               ///< config-relative path of the script ("" if none)
    std::vector<std::string> args;
    std::uint64_t script_seed = 0;
    std::string started_by = "simulation";  ///< "simulation" or "record" (see RunContext)
    std::vector<ConfigFile> files;          ///< without content (read config/PATH)
    std::vector<std::pair<std::string, std::string>> provenance;
};

class RunData {
  public:
    /// Opens a run folder. A missing folder, or one that lacks run.json, series.csv or
    /// data.csv, throws IoError saying what it lacks; malformed content throws FormatError.
    explicit RunData(std::string dir);

    const std::string& dir() const { return dir_; }
    const RunMeta& meta() const { return meta_; }
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

    /// The named series, rows with from <= time <= to.
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

    /// Writes "time,<names...>" and the rows in [from, to] as CSV; throws IoError.
    void write_csv(const std::string& path, const std::vector<std::string>& names,
                   double from = -kInf, double to = kInf) const;

    static constexpr double kInf = std::numeric_limits<double>::infinity();

  private:
    std::string dir_;
    RunMeta meta_;
    std::vector<SeriesInfo> series_;
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
