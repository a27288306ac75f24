#pragma once
// The Open MPI communicator (built only with VPSIM_WITH_MPI; mpi.h stays out of every header).
#include <memory>

#include "vpsim/cluster/communicator.h"

namespace vpsim::cluster {

#ifdef VPSIM_WITH_MPI
/// Initialises MPI (once per process) on MPI_COMM_WORLD; finalised with the last reference.
std::shared_ptr<Communicator> startMpi();
#endif

}  // namespace vpsim::cluster
