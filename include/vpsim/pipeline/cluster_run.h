#pragma once
/// @file
/// `vpsim run` over MPI ranks (started by mpirun/srun; RunContext::cluster): every rank makes the
/// run's collective calls (the beam kernels' Monte Carlo, split by photon batches and merged
/// exactly, transport/mc_split.h), rank 0 alone does the rest and writes the output directory,
/// so the report's figures are the single process's. Tiles of one job use cluster::runItems.

#include <nlohmann/json.hpp>

#include "vpsim/core/run_context.h"
#include "vpsim/pipeline/job.h"
#include "vpsim/pipeline/stages.h"

namespace vpsim::pipeline {

/// A rank other than 0's share of runJob: the collective stages in runJob's order, nothing
/// written. @throw as runJob's stages
void runJobOnWorkerRank(const Job& job, const RunContext& context);

/// report.json's "mpi": the ranks and how the work was split; null in one process.
nlohmann::json clusterSummary(const BeamResult& beam, const RunContext& context);

}  // namespace vpsim::pipeline
