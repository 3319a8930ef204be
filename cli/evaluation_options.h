// The command line `gaitlab optimize` and `gaitlab sweep` share: --workers, --seed,
// --rank-timeout and --out, declared once so that the two read and describe them alike.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace gaitlab::cli {

/// The shared options as the command line gives them (checked when the command runs).
struct EvaluationArgs {
    std::string spec;                 ///< the optimization spec, SPEC.lua
    std::string workers = "1";        ///< threads evaluating, 1 to 1024
    std::string seed = "0";           ///< 0 to 2^64 - 1
    std::string rank_timeout = "30";  ///< s without a word from a rank, under mpirun
    std::string out;                  ///< the results folder; "" : runs/COMMAND-SPEC-DATE-TIME
};

/// Adds --workers, --seed (`seed_help` says what it seeds), --rank-timeout and --out to
/// `command`, in that order, read into `args` (their defaults shown in --help; --out's default
/// folder is named after the command). The spec, args.spec, each command declares first itself:
/// a missing spec is then the first thing said to be missing.
void add_evaluation_options(CLI::App& command, EvaluationArgs& args, const std::string& seed_help);

}  // namespace gaitlab::cli
