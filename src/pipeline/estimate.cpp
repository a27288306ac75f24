#include "vpsim/pipeline/estimate.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "vpsim/core/error.h"
#include "vpsim/core/resources.h"
#include "vpsim/pipeline/stages.h"

#include "estimate_sizes.h"

// Where each term comes from (bytes; keep in step with the code, tests/pipeline/test_estimate.cpp
// compares the peak with a measured one):
//  part mesh         geometry::Mesh: 24 B per vertex (dvec3) + 12 B per triangle, alive to the end.
//  layer stack       geometry::sliceMesh: one contour vertex per triangle crossing a layer's
//                    plane, dvec2 (16 B) in the PolygonSet plus Clipper's int64 copy and the
//                    linked segments while slicing (x3), plus the slicer's 4 B buckets.
//  plan              the planner's estimateSize (planners/plan_size.h); saveScanPlan streams
//                    one layer's nlohmann::json tree at a time: the planner's jsonBytes (a json
//                    array per vector and move, 16 B per mask pixel) over the layers; a saved
//                    plan (--plan) is read as one whole tree.
//  exposure engine   ExposureEngine: deposit, blur pass, running sum, slice (SurfaceGrid floats)
//                    and ExposureModel::forward's deposit: 5 x 4 B per cell. Tabulated engine:
//                    4 B per cell per slice in flight ((layers in flight) x slices + 1) + stencils.
//  dose volume       exposure::DoseVolume: an 8-slice float block buffer (32 B per cell) and the
//                    OpenVDB FloatGrid: 4 B per active voxel in 8^3 leaves (+64 B masks, origin
//                    and internal nodes: 4.5 B per voxel). Active = above 2% of Ec: the part
//                    grown by the beam's reach and a leaf, at most the whole grid.
//  slice consumers   validate::SliceValidator: a raster, three per-column arrays and the reference
//                    raster of each slice (8 B per cell) and its over-cure runs (4 B per cell);
//                    report::SectionRecorder: x-z section (5 B per column and slice) and x-y map;
//                    report::LayerSectionRecorder: the 3D view's per-layer sections (5 B per
//                    kept pixel, at most SECTION_PIXEL_BUDGET of them).
//  cured mesh        DoseVolume::isosurface (OpenVDB volumeToMesh): one quad per surface voxel
//                    face; the cured surface is rougher and larger than the part's (the default
//                    job: 2.8e5 triangles for 1e5 faces of the part's area), so 2 x area /
//                    (pitch x min(pitch, dz)) quads. Our Mesh keeps 24 B per vertex and 2 x 12 B
//                    per quad; volumeToMesh's points, quads and edge/sign masks ~100 B per quad
//                    while it runs.
//  level set         validateStage: geometry::LevelSet::estimateBytes at max(voxel, 20 um).
//  runtime           TBB worker stacks, OpenVDB's registries and library pages first touched.
namespace vpsim::pipeline {

using namespace estimate_detail;

namespace {

void frontTerms(const Job& job, const geometry::Mesh& part, const Sizes& s, JobEstimate& e) {
    add(e, "runtime (threads, libraries)", RUNTIME_BYTES, Stage::Part, Stage::Validate,
        "TBB worker stacks, OpenVDB registries, library pages");
    add(e, "part mesh", 24.0 * part.vertices.size() + 12.0 * part.triangles.size(), Stage::Part,
        Stage::Validate,
        std::to_string(part.triangles.size()) + " triangles, " +
            std::to_string(part.vertices.size()) + " vertices",
        "a mesh with fewer triangles");
    const bool mc = job.machine.process == plan::Process::Laser &&
                    job.kernel.source == kernel::KernelSource::MonteCarlo;
    if (mc) {
        // 80 x 80 (r, z) bins (kernel::kernelSetup), int64, per thread and per batch.
        const double threads = std::max(1u, std::thread::hardware_concurrency());
        add(e, "photon Monte Carlo tallies", 80.0 * 80.0 * 8.0 * (threads + 66.0), Stage::Kernel,
            Stage::Kernel, "80 x 80 (r, z) bins of int64 per thread and per batch");
        e.stageSeconds.emplace_back("kernel", double(job.kernel.photons) * 3e-6);
    }
    add(e, "layer stack (contours)", s.contourVertices * 16.0 * 3.0 + s.layers * 256.0,
        Stage::Slice, Stage::Validate,
        fmt(s.contourVertices) + " contour vertices in " + std::to_string(s.layers) + " layers",
        "thicker layers (machine.layer_thickness) or a mesh with fewer triangles");
    e.stageSeconds.emplace_back("part", 1e-6 * part.triangles.size());
    e.stageSeconds.emplace_back("slice", 2e-6 * s.contourVertices + 1e-5 * s.layers);
}

void planTerms(const Job& job, const Sizes& s, bool savedPlan, JobEstimate& e,
               planners::PlanSize& size) {
    const planners::PlanSizeInputs inputs{
        s.bounds,         s.volume,
        s.layers,         job.machine,
        s.beamRadius,     job.cure->hasPenetrationDepth() ? job.cure->penetrationDepth() : 0.0,
        s.contourVertices};
    size = job.planner->estimateSize(inputs);
    add(e, "scan plan", size.planBytes, Stage::Plan, Stage::Validate, size.detail,
        "thicker layers or a smaller part");
    if (!savedPlan && size.workingBytes > 0)
        add(e, "planner working set (" + job.strategy + ")", size.workingBytes, Stage::Plan,
            Stage::Plan, size.detail, "a coarser planning grid or a smaller part");
    // saveScanPlan streams one layer's tree at a time; a saved plan is read as one whole tree.
    if (savedPlan)
        add(e, "saved plan being read (JSON tree)", size.jsonBytes, Stage::Plan, Stage::Plan,
            "nlohmann::json nodes of every number of the plan file");
    add(e, "plan.json being written (one layer's JSON)", size.jsonBytes / std::max(1, s.layers),
        Stage::Plan, Stage::Plan, "nlohmann::json nodes and text of the largest layer");
    if (!savedPlan) e.stageSeconds.emplace_back("plan", size.seconds);
}

}  // namespace

double contourVertexCount(const geometry::Mesh& part, int layers, double thickness, double zStart,
                          double planePosition) {
    std::vector<double> lo, hi;
    lo.reserve(part.triangles.size());
    hi.reserve(part.triangles.size());
    for (const auto& t : part.triangles) {
        const double a = part.vertices[t[0]].z, b = part.vertices[t[1]].z,
                     c = part.vertices[t[2]].z;
        lo.push_back(std::min({a, b, c}));
        hi.push_back(std::max({a, b, c}));
    }
    std::sort(lo.begin(), lo.end());
    std::sort(hi.begin(), hi.end());
    double total = 0;
    for (int k = 0; k < layers; ++k) {  // triangles with lo <= z minus those with hi < z
        const double z = zStart + (k + planePosition) * thickness;
        total += double(std::upper_bound(lo.begin(), lo.end(), z) - lo.begin()) -
                 double(std::lower_bound(hi.begin(), hi.end(), z) - hi.begin());
    }
    return std::max(total, 0.0);
}

namespace {

JobEstimate estimateWithTiles(const Job& job, const geometry::Mesh& part, bool planOnly,
                              bool savedPlan, bool gpuDriver, double tileSide) {
    JobEstimate e;
    e.job = job.name;
    e.planOnly = planOnly;
    Sizes s = sizesOf(job, part);
    tileSizes(job, tileSide, s);
    e.tileSide = s.tiles > 1 ? tileSide : 0.0;
    e.tileCount = int(s.tiles);
    // As runJob: a tiled run checkpoints after each tile unless it keeps a dose volume.
    e.checkpointed = s.tiles > 1 && !job.simulation.writes("exposure.vdb");
    e.figures = {{"layers", s.layers},
                 {"contour_vertices", s.contourVertices},
                 {"grid_cells", {s.nx, s.ny}},
                 {"slices", s.slices},
                 {"voxels", s.voxels},
                 {"stored_voxels", s.activeVoxels},
                 {"surface_voxels", s.surfaceVoxels}};
    frontTerms(job, part, s, e);
    if (gpuDriver)  // measured: lavapipe's LLVM and the loader, from the first Vulkan call
        add(e, "Vulkan driver", 64 * MIB, Stage::Part, Stage::Validate, "loader and driver");
    planners::PlanSize plan;
    planTerms(job, s, savedPlan, e, plan);
    e.figures["plan_elements"] = plan.elements;
    double referenceVoxels = 0;
    if (!planOnly) {
        exposureTerms(job, s, gpuDriver, e);
        validateTerms(job, part, s, e, referenceVoxels);
    }
    outputTerms(job, part, s, plan, referenceVoxels, e);
    for (const EstimateItem& item : e.items)
        if (item.perTile) e.tileBytes += item.bytes;
    if (s.tiles > 1)
        e.figures["tiles"] = {{"side_mm", tileSide},
                              {"count", s.tiles},
                              {"core_cells", s.coreCells},
                              {"window_cells", s.windowCells}};
    return e;
}

}  // namespace

JobEstimate estimateJob(const Job& job, const geometry::Mesh& part, bool planOnly, bool savedPlan,
                        bool gpuDriver) {
    return estimateWithTiles(job, part, planOnly, savedPlan, gpuDriver, job.simulation.tile);
}

JobEstimate estimateJob(const Job& job, bool planOnly, bool savedPlan, bool gpuDriver) {
    return estimateJob(job, partStage(job), planOnly, savedPlan, gpuDriver);
}

JobEstimate fitEstimate(const Job& job, const geometry::Mesh& part, const RunContext& context,
                        bool planOnly, bool savedPlan, bool gpuDriver) {
    JobEstimate e = estimateJob(job, part, planOnly, savedPlan, gpuDriver);
    const double budget = double(memoryBudget(context));
    if (planOnly || job.simulation.tile > 0 || e.peakBytes() <= budget) return e;
    // Halve the tile's side until the run fits, down to 64 cells (smaller tiles are mostly
    // halo: what still does not fit is not the tiles' to shrink).
    const double pitch = job.simulation.voxel;
    const Sizes whole = sizesOf(job, part);
    for (double side = std::ceil(std::max(whole.nx, whole.ny) / 2.0) * pitch; side >= 64 * pitch;
         side = std::ceil(side / pitch / 2.0) * pitch) {
        JobEstimate tiled = estimateWithTiles(job, part, planOnly, savedPlan, gpuDriver, side);
        if (tiled.peakBytes() <= budget) return tiled;
    }
    return e;  // no tile fits: the whole grid's estimate, which checkEstimate refuses
}

JobEstimate fitEstimate(const Job& job, const RunContext& context, bool planOnly, bool savedPlan,
                        bool gpuDriver) {
    return fitEstimate(job, partStage(job), context, planOnly, savedPlan, gpuDriver);
}

}  // namespace vpsim::pipeline
