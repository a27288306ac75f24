#pragma once
/// @file
/// The laser exposure-error metric (planExposureError, seed 000 Fig. 23) taken from the run's
/// streamed exposure instead of exposing the plan again (issue 22): a SliceSink that reads,
/// of every layer, the voxel slice nearest its top (slice 0). Slices are final when the engine
/// emits them (layers arrive from the top down, each with the print-through of every layer
/// above), so slice 0 of layer k is layer k's total exposure at the slice's centre, dz/2 below
/// its top (dz: the voxel height).
///
/// Depth: the metric is the surface (depth 0) exposure, as planExposureError measures it. The
/// fitted kernel's exposure at depth d is exp(-d/De) times the surface's, for the layer's own
/// light and for every layer's above alike, so `surfaceScale` = exp(dz / (2 De)) turns slice 0
/// into the surface exposure exactly (to float rounding); laserExposureErrorSink
/// (planners/laser_exposure_review.h) uses this sink only with the fitted engine.
///
/// Grid: the run's exposure grid, so a cell's figure is the run's own voxel column (the
/// review's standalone path uses the same grid). Cells of the band beyond the run's grid (a
/// job whose simulation.margin is under Reff) are not counted.
///
/// Tiles and MPI: a tiled run's slices carry the tile's window; the sink counts the tile's core
/// cells only (ExposureSlice::owned) and adds each tile's per-layer sums (its rows' sums added
/// in row order) to the layer's at once, so a tiled run's figures are the tiles' sums in the
/// tiles' order: integer counts and the maximum exactly as untiled, the sums to double
/// rounding. saveState / restoreState (checkpoints) and mergeState (ranks' tiles, merged in the
/// tiles' order) keep that order, so a checkpointed or MPI run gives the single process's bits.

#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/core/binary_state.h"
#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/polygons.h"
#include "vpsim/optimise/laser/exposure_error.h"

namespace vpsim::optimise {

class ExposureErrorSink {
public:
    /// @param grid the run's whole exposure grid
    /// @param regions every layer's region, bottom first (one per plan layer)
    /// @param targetDose Etar (mJ/mm^2); @param band Reff (mm)
    /// @param surfaceScale multiplies slice 0 to give the surface exposure (see above)
    /// @param keepTopMap keep the top layer's surface exposure for a figure (the whole grid's
    ///        cells; not part of the saved state)
    /// @throw InputError for a non-positive Etar or scale, or a negative band
    ExposureErrorSink(const exposure::ExposureGrid& grid, std::vector<geometry::PolygonSet> regions,
                      double targetDose, double band, double surfaceScale, bool keepTopMap);
    ~ExposureErrorSink();
    ExposureErrorSink(ExposureErrorSink&&) noexcept;
    ExposureErrorSink& operator=(ExposureErrorSink&&) noexcept;
    /// A SliceSink: uses slice 0 of each layer with a region, ignores the others.
    void add(const exposure::ExposureSlice& slice);
    /// planExposureError's JSON over the slices seen; `all` (optional) as there.
    nlohmann::json result(ExposureError* all = nullptr);
    /// The top layer's surface exposure (with what any layer above sends) on the run's grid;
    /// empty unless keepTopMap.
    const exposure::SurfaceGrid& topMap() const;
    /// Between two tiles: the per-layer sums and the histogram, for a checkpoint; restoreState
    /// continues from it. @throw InputError for a malformed state
    nlohmann::json saveState();
    void restoreState(const nlohmann::json& state);
    /// Adds the state of a sink that saw later tiles (ranks' tiles, in the tiles' order).
    void mergeState(const nlohmann::json& later);
    /// Checkpoints of a run with figures: the top map so far (record "exposure_error.top_map",
    /// empty unless keepTopMap). @throw InputError naming the state file when it is malformed
    void savePicture(BinaryStateWriter& out) const;
    void restorePicture(const BinaryStateReader& in);
    /// An MPI rank's tile, seen alone: the top map's cells of the tile's `core` (record
    /// "exposure_error.tile_top_map", empty unless keepTopMap); mergePicture copies them in.
    void savePartialPicture(BinaryStateWriter& out, const exposure::CellWindow& core) const;
    void mergePicture(const BinaryStateReader& in, const exposure::CellWindow& core);

private:
    struct State;
    std::unique_ptr<State> mState;
};

}  // namespace vpsim::optimise
