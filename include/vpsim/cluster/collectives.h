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

/// Pieces of MPI messages that streamToRoot sends: far below MPI's int counts, and what rank 0
/// and the owner hold of a stream at a time.
constexpr size_t STREAM_CHUNK_BYTES = size_t(64) << 20;

/// `total` bytes that rank `owner` holds (read(offset, count) there gives them) passed to rank 0
/// (write(piece) there, in order) in pieces of at most `chunk` bytes, so that neither rank holds
/// more than one piece: a tile's STL of many GB, which one message could not carry (MPI counts
/// are int) and no rank could hold. Collective: every rank calls it with the same owner, total
/// and chunk. read and write are called on their rank only; owner 0 streams to itself.
/// @throw Error on the owner when read gives fewer bytes than asked
void streamToRoot(Communicator& comm, int owner, uint64_t total,
                  const std::function<std::string(uint64_t offset, size_t count)>& read,
                  const std::function<void(const std::string&)>& write,
                  size_t chunk = STREAM_CHUNK_BYTES);

}  // namespace vpsim::cluster
