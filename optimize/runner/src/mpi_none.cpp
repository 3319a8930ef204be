// Built without MPI (see gaitlab/optimize/mpi.h): gaitlab optimize runs on threads only.
#include "gaitlab/error.h"
#include "gaitlab/optimize/mpi.h"

namespace gaitlab::optimize {

namespace {
[[noreturn]] void not_built() {
    throw Error(
        "this gaitlab was built without MPI (install libopenmpi-dev and build again: "
        "docs/optimization.md, \"On a cluster: MPI\")");
}
}  // namespace

bool mpi_built() {
    return false;
}

MpiSession::MpiSession() {
    not_built();
}

MpiSession::~MpiSession() = default;

std::unique_ptr<EvaluationBackend> make_mpi_backend(MpiSession&, const MpiOptions&) {
    not_built();
}

int mpi_serve(MpiSession&, const std::string&, const MpiOptions&, const std::atomic<int>*) {
    not_built();
}

}  // namespace gaitlab::optimize
