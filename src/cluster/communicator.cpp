// Launch detection and the choice between MPI and one process.
#include "vpsim/cluster/communicator.h"

#include <cstdlib>

#include "mpi_communicator.h"
#include "vpsim/core/error.h"

namespace vpsim::cluster {
namespace {

int positiveOr1(const char* text) {
    if (!text || !*text) return 1;
    const long value = std::strtol(text, nullptr, 10);
    return value > 0 ? int(value) : 1;
}

}  // namespace

int LaunchEnvironment::worldSize() const {
    return ompiWorldSize ? positiveOr1(ompiWorldSize) : positiveOr1(pmiSize);
}

bool LaunchEnvironment::launched() const {
    return ompiWorldSize || pmiSize || pmixRank;
}

bool builtWithMpi() {
#ifdef VPSIM_WITH_MPI
    return true;
#else
    return false;
#endif
}

std::shared_ptr<Communicator> startCommunicator(const LaunchEnvironment& environment) {
    if (!environment.launched()) return std::make_shared<SingleProcess>();
#ifdef VPSIM_WITH_MPI
    return startMpi();
#else
    if (environment.worldSize() > 1)
        throw InputError("started by an MPI launcher with " +
                             std::to_string(environment.worldSize()) +
                             " processes, but this vpsim was built without MPI (install "
                             "libopenmpi-dev and rebuild, or run without mpirun/srun)",
                         "", "OMPI_COMM_WORLD_SIZE");
    return std::make_shared<SingleProcess>();
#endif
}

}  // namespace vpsim::cluster
