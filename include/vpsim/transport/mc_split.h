#pragma once
/// @file
/// One photon Monte Carlo run spread over the ranks of a Communicator (MPI) and merged exactly.
/// Photon i has its own random stream and tallies into batch i % MC_BATCHES and control batch
/// i % MC_CONTROL_BATCHES whichever process traces it, and every tally is an integer, so each
/// rank traces a contiguous range of photon indices (whole rounds of the 1024 control batches)
/// and the ranks' tallies, added as integers, are the single process's bit for bit; the
/// collision estimator's bins are scaled to quanta and a Gaussian beam's pencil response is
/// convolved only after the addition. Everything derived (the control-variate fit, the kernel)
/// is then computed from the same integers on every rank.

#include <memory>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/cluster/communicator.h"
#include "vpsim/transport/photon_mc.h"

namespace vpsim::transport {

/// Photons [first, first + count) of the run that `rank` of `ranks` traces (offsets from the
/// setup's firstPhoton): whole multiples of MC_CONTROL_BATCHES, the last rank taking the rest.
struct PhotonShare {
    uint64_t first = 0, count = 0;
};
PhotonShare photonShare(uint64_t photons, int rank, int ranks);

/// What runPhotonMcSplit did, for report.json's "mpi": ranks and each rank's photon range.
nlohmann::json photonSplitJson(uint64_t photons, int ranks);

/// Runs `setup` over all ranks of `comm` (a collective call: every rank calls it with the same
/// setup) and returns the merged result on every rank; with one rank it is runPhotonMc.
/// @throw as runPhotonMc
McResult runPhotonMcSplit(const McSetup& setup, const std::shared_ptr<gpu::Context>& context,
                          cluster::Communicator& comm);

}  // namespace vpsim::transport
