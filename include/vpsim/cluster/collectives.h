#pragma once
/// @file
/// Collective helpers over a Communicator: deterministic double sums, JSON gathers, and the
/// distribution of n independent work items (jobs of a batch, tiles of a job) over the ranks
/// with their results gathered to rank 0 in index order.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/cluster/communicator.h"

namespace vpsim::cluster {

/// Element-wise sum of every rank's `values`, added in rank order (rank 0's first) on rank 0
/// and sent to all, so the result is the same bits whatever the timing. Sizes must agree.
std::vector<double> sumInRankOrder(Communicator& comm, const std::vector<double>& values);

/// Each rank's JSON on rank 0, in rank order; empty on the other ranks.
std::vector<nlohmann::json> gatherJson(Communicator& comm, const nlohmann::json& mine);

/// The rank that owns item `index` of n: round-robin (index % ranks), so neighbouring items
/// (tiles of similar cost, jobs of a sweep) spread evenly.
int ownerOfItem(size_t index, int ranks);
/// The items of 0..n-1 this rank owns, in increasing order.
std::vector<size_t> itemsOfRank(size_t n, int rank, int ranks);

/// Runs work(i) for the items this rank owns and returns, on rank 0, all n results in index
/// order (empty on the other ranks). work's result is opaque bytes (a partial tally, a tile's
/// statistics, a job's summary) that the caller merges in index order, so the merged result is
/// the single process's. An exception in work propagates on its rank only: catch it inside work
/// and encode it when the other ranks must carry on.
std::vector<std::string> runItems(Communicator& comm, size_t n,
                                  const std::function<std::string(size_t)>& work);

}  // namespace vpsim::cluster
