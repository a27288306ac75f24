#pragma once
/// @file
/// The stages of a run, each a function from typed inputs to a typed output that can be saved
/// and loaded (docs/ARCHITECTURE.md): part (part.stl) -> beam kernel (kernel/kernel.json) -> layer
/// stack (LayerStack JSON) -> scan plan (plan.json) -> exposure, streamed to slice consumers
/// (exposure.vdb) -> cured part (cured.stl) -> validation report (report.json).

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vpsim/core/run_context.h"
#include "vpsim/cure/cure_law.h"
#include "vpsim/exposure/dose_volume.h"
#include "vpsim/exposure/exposure_model.h"
#include "vpsim/exposure/tiles.h"
#include "vpsim/geometry/layer_stack.h"
#include "vpsim/geometry/mesh.h"
#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/pipeline/job.h"
#include "vpsim/plan/machine/scan_report.h"
#include "vpsim/report/job_result.h"
#include "vpsim/validate/streaming_surface.h"

namespace vpsim::pipeline {

/// The part on the build platform. @throw InputError for unreadable or broken STL files
geometry::Mesh partStage(const Job& job);

/// The beam the plan and the exposure use.
struct BeamResult {
    kernel::FittedBeam beam;                       ///< fitted, given, or the DLP projector blur
    std::optional<kernel::BeamKernel> monteCarlo;  ///< the Monte Carlo kernel, when one was run
    bool fromCache = false;
    /// The planning kernel's beam when the job names one apart (`kernel.plan`), with its Monte
    /// Carlo kernel when it has one; the exposure and validation use `beam`.
    std::optional<kernel::FittedBeam> planBeam;
    std::optional<kernel::BeamKernel> planMonteCarlo;
    bool planFromCache = false;
    /// What the planner plans with: planBeam when there is one, else beam.
    const kernel::FittedBeam& planningBeam() const { return planBeam ? *planBeam : beam; }
};
/// Laser jobs: the Monte Carlo kernel of the material (cached) or the given one, and the same
/// for the planning kernel (`kernel.plan`) when there is one; DLP jobs: the projector blur with
/// the resin's penetration depth.
BeamResult beamStage(const Job& job, const RunContext& context);

/// The part sliced into the machine's layers from z = 0.
geometry::LayerStack sliceStage(const Job& job, const geometry::Mesh& part);

struct PlanResult {
    plan::ScanPlan plan;
    nlohmann::json summary = nlohmann::json::object();  ///< the planner's figures
};
/// Runs the job's planner with the planning beam (BeamResult::planningBeam()); `part` is the
/// part's mesh when the caller has it. @throw InputError from the planner
PlanResult planStage(const Job& job, const geometry::LayerStack& layers,
                     const geometry::Bounds& partBounds, const BeamResult& beam,
                     const RunContext& context, const geometry::Mesh* part = nullptr);

/// The scanner's view of the plan (seed 002, seed 000 III-C): each laser layer's parts ordered
/// (`plan.order`) into mark and jump trajectories stored in the plan, unless the plan already has
/// them (a saved plan), and the build time (`machine.scanner`, recoat, DLP mask exposure).
/// @throw InputError from the ordering or the build-time model
plan::ScanSchedule scanStage(const Job& job, const geometry::LayerStack& layers,
                             plan::ScanPlan& plan);

/// Adds the schedule's figures (build time, scan order, laser use) to report.json's "plan"
/// "planner" object `planner`.
void addScheduleFigures(const plan::ScanSchedule& schedule, nlohmann::json& planner);

/// Writes scan_path.svg (the busiest layer's marks, jumps and order) into `outDir` when
/// `figures` (simulation.outputs) asks for it; the machine files (scan.cli, ...) come from
/// exportStage.
void writeScanFiles(const plan::ScanSchedule& schedule, const plan::ScanPlan& plan,
                    const std::string& outDir, bool figures);

/// Checks that a saved (or hand-edited) plan fits the job: the same process, layer thickness
/// and number of layers as the sliced part. @throw InputError naming `file`
void checkPlanFitsJob(const plan::ScanPlan& plan, const Job& job,
                      const geometry::LayerStack& layers, const std::string& file);

/// Writes the plan with each of the job's exporters that can express it (into `outDir`, under
/// the exporter's file name); returns the files written. Exporters that cannot are skipped
/// with an info line saying why.
std::vector<std::string> exportStage(const Job& job, const plan::ScanPlan& plan,
                                     const std::string& outDir);

/// The grid the exposure is computed on: the part's footprint plus the margin.
exposure::ExposureGrid exposureGrid(const Job& job, const geometry::Bounds& partBounds,
                                    const BeamResult& beam);
/// The exposure model of the job (fitted or tabulated), on the GPU where the context says so.
std::unique_ptr<exposure::ExposureModel> exposureModel(const Job& job,
                                                       const exposure::ExposureGrid& grid,
                                                       const BeamResult& beam,
                                                       const RunContext& context);
/// The x-y tiles of `grid` for a core side of `tileSide` mm (0: one tile, the whole grid),
/// with a halo of the model's reach plus the one cell the cured-surface mesher looks beside.
std::vector<exposure::Tile> exposureTiles(const exposure::ExposureModel& model, double tileSide);
/// Called after each tile's last slice (a checkpoint's moment).
using TileDone = std::function<void(const exposure::Tile&)>;
/// Exposes `plan` tile after tile (in the tiles' order: consumers merge in that fixed order),
/// streaming every slice to each of `consumers` in turn. `model` is the whole grid's; a tile
/// runs on a model of its window (exposureModel), or on `model` itself when there is one tile.
/// Several tiles: those from `firstTile` on (the earlier ones done by an interrupted run), each
/// followed by `afterTile` when given.
report::ExposureSummary exposeStage(const Job& job, exposure::ExposureModel& model,
                                    const std::vector<exposure::Tile>& tiles,
                                    const plan::ScanPlan& plan,
                                    const std::vector<exposure::SliceSink>& consumers,
                                    const BeamResult& beam, int layers, const RunContext& context,
                                    int firstTile = 0, const TileDone& afterTile = {});

/// Half-width (mm) of the band within which surface deviations are measured (farther ones are
/// clamped to it and counted as beyond the band): a few beam radii, 0.25 mm at least (print-through
/// over-cure), in whole reference voxels of max(voxel, 20 um), as the reference level set's.
double deviationBand(const Job& job);

/// The cured part's surface, meshed while the engine emits its slices (a SliceSink), written to
/// `stlPath` ("" for none; `inPlace`: written there directly, so that it can be resumed) and
/// measured against `part` on the way.
std::unique_ptr<validate::StreamingCuredSurface> curedSurfaceSink(
    const Job& job, const exposure::ExposureGrid& grid, double voxelHeight,
    const geometry::Mesh& part, const std::string& stlPath, bool inPlace = false);

/// Closes the cured surface (its bottom and its STL). @throw InputError when nothing cures
void cureStage(validate::StreamingCuredSurface& cured);

/// Surface deviation of the cured surface (exact distances taken as it was meshed), with the
/// slice statistics and features gathered while exposing. Builds and writes the part's signed
/// distance field to `referenceVdb` only when that is not "".
report::ValidationReport validateStage(const Job& job, const geometry::Mesh& part,
                                       const validate::StreamingCuredSurface& cured,
                                       validate::SliceValidationSummary slices,
                                       validate::FeatureMeasurements features,
                                       const std::string& referenceVdb);

}  // namespace vpsim::pipeline
