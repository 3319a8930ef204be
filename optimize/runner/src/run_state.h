// The state of a run in its results folder, OUT/state.json, written after every generation so
// that `gaitlab optimize --resume` continues an interrupted run where it was
// (docs/optimization.md, "Resuming an interrupted run").
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace gaitlab::optimize::detail {

/// What a resumed run must agree on and where it goes on from.
struct RunState {
    std::string spec_file;          ///< the spec file, as given
    std::string spec_text;          ///< its whole text: a resumed run's spec must be the same
    std::string method;             ///< "ga", "cmaes" or "pgpe"
    int population = 0;             ///< as asked for (0: the method's default)
    int generations = 0;            ///< the run's length
    std::uint64_t seed = 0;         ///< the method's seed
    std::string command;            ///< the command line that began the run (best.json keeps it)
    int first_population = 0;       ///< individuals of generation 0 (0: not asked yet)
    int generation = 0;             ///< generations done
    std::uint64_t jsonl_bytes = 0;  ///< length of evaluations.jsonl after them
    double wall = 0;                ///< wall seconds spent on them, over every session
    std::string method_state;       ///< Method::save() after them
};

/// The text of a spec file; IoError when it cannot be read.
std::string read_text_file(const std::filesystem::path& path);

/// Writes OUT/state.json: to a temporary file, flushed to the disk, then renamed, so that a
/// kill at any moment leaves the previous state or the new one, never half of one. IoError.
void write_run_state(const std::filesystem::path& out, const RunState& state);

/// Reads OUT/state.json. SpecError naming the file and what is wrong ("--out DIR: no run to
/// resume ..." when there is none).
RunState read_run_state(const std::filesystem::path& out);

/// Checks that a run begun as `saved` may be resumed as `now` (the same spec text, method,
/// population, generations and seed); SpecError saying what differs otherwise.
void check_resumable(const RunState& saved, const RunState& now, const std::filesystem::path& out);

}  // namespace gaitlab::optimize::detail
