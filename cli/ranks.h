// What `gaitlab optimize` and `gaitlab sweep` do under mpirun (gaitlab/optimize/mpi.h,
// docs/optimization.md "On a cluster: MPI"): rank 0 runs the command and hands its evaluations
// to ranks 1 .. K-1, which evaluate them on their own threads until rank 0 says stop.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "gaitlab/optimize/mpi.h"
#include "gaitlab/optimize/runner.h"

namespace gaitlab::cli {

/// Adds --rank-timeout to `command` (gaitlab optimize, gaitlab sweep), read into `text` (its
/// default shown in --help); rank_timeout_option reads it.
void add_rank_timeout_option(CLI::App& command, std::string& text);

/// --rank-timeout's text: seconds > 0; SpecError "--rank-timeout: a number of seconds > 0
/// expected (got 'TEXT')" otherwise.
double rank_timeout_option(const std::string& text);

/// MPI for one command. Not under mpirun: nothing (no backend, not serving).
struct Ranks {
    std::unique_ptr<optimize::MpiSession> session;
    /// On rank 0 of two or more ranks: hands the evaluations out (destroyed before the session:
    /// it tells the ranks to stop)
    std::unique_ptr<optimize::EvaluationBackend> backend;
    /// On ranks 1 .. K-1: the exit status once rank 0 said stop (-1 on rank 0 or without MPI)
    int served = -1;
};

/// Starts MPI when this process was started by mpirun: ranks >= 1 load `spec` and evaluate
/// until rank 0 says stop (or `stop` becomes non-zero), rank 0 gets the backend. Rank 0 warns on
/// stderr when a rank is given up. Throws Error (MPI not built in, the spec not loaded).
Ranks start_ranks(const std::string& spec, optimize::MpiOptions options,
                  const std::atomic<int>* stop);

/// How `gaitlab optimize` and `gaitlab sweep` begin: start_ranks(`file`, `options`), stopped by
/// evaluations_stop(), into `mpi`, then the spec `file` loaded into `spec`. Returns -1 on rank
/// 0 (the command goes on; mpi.backend, if any, evaluates), else the status to exit with: a
/// serving rank's once rank 0 said stop, or 1 with the error on stderr.
int start_ranks_and_load(const std::string& file, const optimize::MpiOptions& options, Ranks& mpi,
                         optimize::Spec& spec);

/// Who evaluates, as the command's first line says it: "2 workers", or under mpirun the
/// backend's description.
std::string workers_text(const Ranks& mpi, int workers);

}  // namespace gaitlab::cli
