#pragma once
/// @file
/// The up-front estimate of a job (issue 13 item 2): memory of each large structure a run holds,
/// the output files' sizes and a rough time, computed from the parsed job and its part mesh
/// alone, before the kernel is computed, the part sliced or anything written. runJob and planJob
/// refuse a job whose peak exceeds the memory budget (core/resources.h) with the estimate's
/// figures; `vpsim run JOB --dry-run` prints it.
///
/// The model follows the code (each term's origin is documented in estimate.cpp): the run
/// keeps the part mesh, the layer stack and the plan from start to end; the exposure streams
/// slices from a 2D engine into the sparse OpenVDB dose volume (kept until the end) and the
/// slice consumers; the cure stage meshes the volume's isosurface; validation builds the part's
/// narrow-band level set. The peak is the largest sum over the stages of what is alive in each.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/core/run_context.h"
#include "vpsim/geometry/mesh.h"
#include "vpsim/pipeline/job.h"

namespace vpsim::pipeline {

/// The stages in run order; an estimate item lives from its first to its last stage.
enum class Stage { Part, Kernel, Slice, Plan, Expose, Cure, Validate };
/// "part", "kernel", "slice", "plan", "expose", "cure", "validate".
const char* stageName(Stage stage);

/// One structure of the run and its memory.
struct EstimateItem {
    std::string name;                                   ///< e.g. "exposure dose volume (OpenVDB)"
    double bytes = 0;                                   ///< upper estimate
    Stage first = Stage::Part, last = Stage::Validate;  ///< alive in [first, last]
    std::string detail;    ///< how the figure follows from the job (sizes, bytes per element)
    std::string hint;      ///< how to make it smaller (for refusals), "" when nothing helps
    bool perTile = false;  ///< held for one x-y tile at a time: what tiles shrink
};

/// One output file and its estimated size.
struct OutputEstimate {
    std::string file;  ///< name inside the output directory
    double bytes = 0;
};

struct JobEstimate {
    std::string job;                      ///< the job's name
    bool planOnly = false;                ///< `vpsim plan`: the stages up to the plan
    std::vector<EstimateItem> items;      ///< memory, largest structures of the run
    std::vector<OutputEstimate> outputs;  ///< files written
    std::vector<std::pair<std::string, double>> stageSeconds;  ///< rough time per stage
    /// Sizes the terms follow from: grid cells, voxels, layers, vectors, pixels.
    nlohmann::json figures = nlohmann::json::object();
    /// The run's x-y tiles (simulation.tile, or chosen by fitEstimate): the side of a tile's
    /// core (mm; 0: the whole grid in one tile), how many, and the bytes that one tile's
    /// structures hold (what tiling bounds; the rest grows with the part's surface or is
    /// whole-part output).
    double tileSide = 0;
    int tileCount = 1;
    double tileBytes = 0;
    bool checkpointed = false;  ///< a checkpoint after each tile (pipeline/checkpoint.h)

    /// Bytes alive in `stage`: the sum of the items whose span contains it.
    double bytesAt(Stage stage) const;
    /// The stage with the most bytes alive, and those bytes.
    Stage peakStage() const;
    double peakBytes() const { return bytesAt(peakStage()); }
    double outputBytes() const;
    double seconds() const;
    /// {"job", "peak_bytes", "peak_stage", "budget_bytes", "memory": [...], "outputs": [...],
    /// "seconds", ...}; the budget is memoryBudget(context) (core/resources.h).
    nlohmann::json toJson(const RunContext& context) const;
    /// A readable table (memory by item with its span, outputs, time, the budget of `context`),
    /// lines ending in '\n'.
    std::string table(const RunContext& context) const;
};

/// What a run (or `vpsim plan`, planOnly) of `job` on `part` (the loaded part mesh) will hold,
/// write and take. `savedPlan`: the plan comes from a file, so the planner does not run;
/// `gpuDriver`: a Vulkan context is open (its driver's memory counts, ~64 MiB for lavapipe).
/// Allocates nothing large; O(triangles log triangles).
JobEstimate estimateJob(const Job& job, const geometry::Mesh& part, bool planOnly = false,
                        bool savedPlan = false, bool gpuDriver = false);

/// The same, loading the part first (partStage). @throw InputError for an unreadable part
JobEstimate estimateJob(const Job& job, bool planOnly = false, bool savedPlan = false,
                        bool gpuDriver = false);

/// The estimate with the x-y tiles that fit memoryBudget(context): the job's simulation.tile
/// when set; otherwise the whole grid when it fits, else the largest tile (halving the side)
/// whose run fits, else the whole grid's (checkEstimate then refuses: what does not fit is not
/// what tiles shrink).
JobEstimate fitEstimate(const Job& job, const geometry::Mesh& part, const RunContext& context,
                        bool planOnly = false, bool savedPlan = false, bool gpuDriver = false);
/// The same, loading the part first (partStage). @throw InputError for an unreadable part
JobEstimate fitEstimate(const Job& job, const RunContext& context, bool planOnly = false,
                        bool savedPlan = false, bool gpuDriver = false);

/// @throw ResourceError when the outputs the estimate lists do not fit the free space of the
/// file system that `outDir` (or its nearest existing parent) is on.
void checkDisk(const JobEstimate& estimate, const std::string& outDir);

/// @throw ResourceError when the estimate's peak exceeds memoryBudget(context): the message names
/// the job, the peak and its stage, the largest items with their sizes, the budget and how to fit.
void checkEstimate(const JobEstimate& estimate, const RunContext& context);

/// Contour vertices of `layers` slices of `part` (one per triangle crossing a slicing plane at
/// zStart + (k + planePosition) x thickness), for sizing a layer stack before slicing (16 B per
/// vertex in a PolygonSet). O(triangles log triangles + layers log triangles).
double contourVertexCount(const geometry::Mesh& part, int layers, double thickness, double zStart,
                          double planePosition);

}  // namespace vpsim::pipeline
