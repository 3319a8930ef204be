// Whether an MPI launcher started this process (see gaitlab/optimize/mpi.h): built with and
// without MPI, so that a gaitlab built without it refuses to run as K copies under mpirun.
#include <cstdlib>

#include "gaitlab/optimize/mpi.h"

namespace gaitlab::optimize {

bool mpi_launched() {
    // OpenMPI's mpirun; PMIx (OpenMPI, srun --mpi=pmix); PMI-1/2 (srun --mpi=pmi2, MPICH)
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"}) {
        if (std::getenv(name) != nullptr) return true;
    }
    return false;
}

}  // namespace gaitlab::optimize
