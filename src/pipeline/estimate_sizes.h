#pragma once
// Private to src/pipeline: what the estimate's terms are computed from (estimate.cpp: the terms
// up to the plan and the whole estimate; estimate_sizes.cpp: the grid, the tiles and the texts;
// estimate_terms.cpp: the terms of the exposure, the validation and the output files).

#include <string>

#include "vpsim/core/text.h"
#include "vpsim/geometry/mesh.h"
#include "vpsim/pipeline/estimate.h"
#include "vpsim/pipeline/job.h"
#include "vpsim/planners/plan_size.h"

namespace vpsim::pipeline::estimate_detail {

constexpr double MIB = 1024.0 * 1024.0;
constexpr double RUNTIME_BYTES = 48 * MIB;
constexpr double VDB_BYTES_PER_VOXEL = 4.5;
constexpr double VDB_LEAF = 8;  ///< voxels per leaf edge
extern const char* const COARSER;

inline std::string fmt(double value, int digits = 3) {
    return formatNumber(value, digits);
}

/// The sizes every term follows from.
struct Sizes {
    geometry::Bounds bounds;
    double volume = 0, area = 0;
    int layers = 0;
    double contourVertices = 0;
    double beamRadius = 0;  ///< upper guess of the fitted We3D (mm)
    double nx = 0, ny = 0, cells = 0, slices = 0, voxels = 0, voxelHeight = 0;
    double activeVoxels = 0, surfaceVoxels = 0;
    /// Grid edges the part's surface crosses: each is a quad of the cured surface (the mesher
    /// is dual: a vertex per crossed cell, a quad per crossed edge), so cured.stl's triangles.
    double surfaceEdges = 0;
    // x-y tiles: core side (cells; 0 = one tile), count, the largest core and window, and the
    // windows' cells summed over the tiles (what the engine computes).
    double tileCells = 0, tiles = 1, coreCells = 0, windowCells = 0, computedCells = 0;
};

/// Whether the run exposes with the tabulated Monte Carlo kernel (a laser job's kernel.use).
inline bool tabulatedEngine(const Job& job) {
    return job.kernel.tabulated && job.machine.process == plan::Process::Laser;
}

/// The part's sizes and the exposure grid's (one tile).
Sizes sizesOf(const Job& job, const geometry::Mesh& part);
/// Tiles of `side` mm (0: one) as stages.cpp's exposureTiles() lays them out; the halo is the
/// engine's reach plus the mesher's cell: the fitted blur's half-width (1.75 W, the radius
/// sizesOf guesses), or for the tabulated engine its widest stencil, at most the kernel table's
/// radius (the Monte Carlo has not run yet, so its bound).
void tileSizes(const Job& job, double side, Sizes& s);

void add(JobEstimate& e, std::string name, double bytes, Stage first, Stage last,
         std::string detail, std::string hint = "", bool perTile = false);
std::string gridText(const Job& job, const Sizes& s);
/// ", per tile of ..." when the run is tiled, else "".
std::string tileText(const Sizes& s);

/// The exposure's terms; `gpuDriver`: the exposure shaders run (on any Vulkan device).
void exposureTerms(const Job& job, const Sizes& s, bool gpuDriver, JobEstimate& e);
void validateTerms(const Job& job, const geometry::Mesh& part, const Sizes& s, JobEstimate& e,
                   double& referenceVoxels);
void outputTerms(const Job& job, const geometry::Mesh& part, const Sizes& s,
                 const planners::PlanSize& plan, double referenceVoxels, JobEstimate& e);

}  // namespace vpsim::pipeline::estimate_detail
