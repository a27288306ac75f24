#pragma once
/// @file
/// `vpsim run` over MPI ranks (started by mpirun/srun; RunContext::cluster): every rank makes the
/// run's collective calls (the beam kernels' Monte Carlo, split by photon batches and merged
/// exactly, transport/mc_split.h), rank 0 alone does the rest and writes the output directory,
/// so the report's figures are the single process's. The x-y tiles of a job (without
/// exposure.vdb, whose state is the whole volume) are dealt round-robin over the ranks
/// (cluster::runItems): each rank exposes its tiles into fresh consumers and picture recorders
/// (picture_recorders.h), and rank 0 merges their states and their shares of the pictures in
/// the tiles' order, as one process would, to the bit.

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/core/run_context.h"
#include "vpsim/optimise/laser/exposure_error_sink.h"
#include "vpsim/pipeline/checkpoint.h"
#include "vpsim/pipeline/job.h"
#include "vpsim/pipeline/stages.h"
#include "vpsim/validate/feature_probe.h"
#include "vpsim/validate/slice_validator.h"

namespace vpsim::pipeline {

/// A rank other than 0's share of runJob: the collective stages in runJob's order (the beam
/// kernel, then the tiles rank 0 sends, when it does), nothing written. @throw as runJob's stages
void runJobOnWorkerRank(const Job& job, const RunContext& context);

/// The slice consumers whose states are small: what a tile's result, a checkpoint
/// (checkpoint.h) and rank 0's merge carry. The one list of them: a consumer added here is
/// saved, restored and merged everywhere.
struct TileConsumers {
    validate::SliceValidator& validator;
    validate::StreamingCuredSurface& cured;
    validate::FeatureProbes& features;
    /// The laser review's exposure error (planners::laserExposureErrorSink), or nullptr.
    optimise::ExposureErrorSink* exposureError = nullptr;

    nlohmann::json save() const;
    /// Before the first slice: the state save() gave (a checkpoint's, read from `file`).
    /// @throw InputError naming `file` when a consumer's state is missing or malformed
    void restore(const nlohmann::json& state, const std::string& file) const;
    /// Appends the tiles of another set of consumers (its save()); their STL's triangles follow
    /// through cured.appendStl.
    void merge(const nlohmann::json& later) const;
};

/// Rank 0, once the plan is made (every run under MPI: the other ranks wait for it): the tiles
/// to share, or none. `plan` is the plan to expose; `tileSide` exposureTiles' side; the tiles
/// before `firstTile` are done (a resumed run's). With `stl`, every rank then checks that its
/// temporary directory has room for `tileStlBytes` (checkTileScratch).
/// @throw ResourceError (rank 0) when a rank's has not, before any tile is exposed
void sendTileWork(const RunContext& context, bool distributed, double tileSide,
                  const plan::ScanPlan& plan, bool stl, int firstTile, double tileStlBytes);

/// Every rank (collective): whether its temporary directory (TMPDIR) has `bytes` free, the
/// share of cured.stl that one tile of a distributed run keeps there until rank 0 takes it.
/// Returns true when every rank's has; otherwise rank 0 throws a ResourceError naming the ranks
/// short of room and the others return false.
bool checkTileScratch(cluster::Communicator& comm, double bytes);

/// Every rank: the tiles from `firstTile` on that it owns (tile firstTile + k on rank
/// k % ranks), each exposed into fresh consumers, one round of a tile per rank at a time; on
/// rank 0, `merge` takes each tile's partial result (consumers' saveState and its share of the
/// pictures) in the tiles' order, then `appendStl` the tile's STL triangles in pieces of at
/// most cluster::STREAM_CHUNK_BYTES (each rank keeps its tile's STL in a file of the temporary
/// directory until then), and `roundDone` the number of tiles done after each round's merge.
void exposeTilesOnRanks(const Job& job, const geometry::Mesh& part,
                        const exposure::ExposureModel& model,
                        const std::vector<exposure::Tile>& tiles, const plan::ScanPlan& plan,
                        const BeamResult& beam, const RunContext& context, bool stl, int firstTile,
                        const std::function<void(const std::string&)>& merge,
                        const std::function<void(const std::string&)>& appendStl,
                        const std::function<void(int)>& roundDone);

/// Rank 0: merges one tile's partial result into the run's consumers and pictures (call in the
/// tiles' order; the tile's STL triangles follow through cured.appendStl).
/// @throw InputError when the result is malformed
void mergeTilePartial(const std::string& partial, const std::vector<exposure::Tile>& tiles,
                      const TileConsumers& consumers, const PictureConsumers& pictures);

/// report.json's "mpi" "tiles": how many and which rank exposed each (from `firstTile` on).
nlohmann::json tileSplitJson(size_t tiles, int ranks, int firstTile);

/// report.json's "mpi": the ranks and how the work was split; null in one process.
nlohmann::json clusterSummary(const BeamResult& beam, const RunContext& context);

}  // namespace vpsim::pipeline
