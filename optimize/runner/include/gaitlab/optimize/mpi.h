// The MPI backend of gaitlab optimize (docs/optimization.md, "On a cluster: MPI"). Under
// `mpirun -n K`, rank 0 runs the method and hands individuals out; ranks 1 .. K-1 evaluate them,
// each on its own threads (--workers), and send the results back; results are stored by
// individual, so a run gives the same result as on threads. A rank that stops answering (dead,
// its node lost) is given up after a timeout: its evaluations go to the other ranks; when none
// is left, the batch throws Error. Built only with an MPI (CMake GAITLAB_MPI, Debian
// libopenmpi-dev); without one, mpi_launched() is false and the rest throws Error.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "gaitlab/optimize/backend.h"

namespace gaitlab::optimize {

struct Spec;

/// True when gaitlab was built with MPI.
bool mpi_built();

/// True when this process was started by an MPI launcher (mpirun, mpiexec, srun with PMIx or
/// PMI): its environment says so, whether gaitlab was built with MPI or not. MPI is initialised
/// only then (a plain run never touches it).
bool mpi_launched();

/// MPI for the life of this object: MPI_Init_thread on construction, MPI_Finalize on
/// destruction; after a rank was given up, MPI_Abort instead (OpenMPI's MPI_Finalize waits for
/// every rank, the lost ones too): the job ends, its other ranks with it. One per process.
class MpiSession {
  public:
    MpiSession();
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;
    int rank() const { return rank_; }
    int size() const { return size_; }

  private:
    int rank_ = 0;
    int size_ = 1;
};

/// How the ranks work.
struct MpiOptions {
    int workers = 1;           ///< threads per evaluating rank, >= 1
    double rank_timeout = 30;  ///< seconds without a word from a rank before it is given up
    std::uint64_t seed = 0;    ///< seeds math.random before every evaluation (a sweep's --seed)
    /// on rank 0: told when a rank is given up ("rank 2: no word for 30 s: its 2 evaluations
    /// go to the other ranks")
    std::function<void(const std::string&)> warn;
};

/// On rank 0 (size >= 2): the backend that hands individuals to ranks 1 .. size-1. Waits for
/// each rank to load the spec; a rank that cannot is given up (its message is kept, see
/// lost()). Destroying it tells the ranks to stop.
std::unique_ptr<EvaluationBackend> make_mpi_backend(MpiSession& session, const MpiOptions& options);

/// On ranks 1 .. size-1: loads the spec, evaluates what rank 0 sends until it says stop, and
/// returns 0. A spec that does not load is reported to rank 0 (which ends the run with the
/// message), then it waits for stop. When `stop` becomes non-zero (a signal's number), the
/// evaluations under way are interrupted and it returns 128 + that number.
int mpi_serve(MpiSession& session, const std::string& spec_file, const MpiOptions& options,
              const std::atomic<int>* stop = nullptr);

}  // namespace gaitlab::optimize
