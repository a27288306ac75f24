#include "vpsim/pipeline/estimate.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "vpsim/core/error.h"
#include "vpsim/core/resources.h"
#include "vpsim/core/text.h"
#include "vpsim/geometry/level_set.h"
#include "vpsim/geometry/slicer.h"
#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/pipeline/stages.h"
#include "vpsim/report/layer_sections.h"
#include "vpsim/report/viewer3d.h"

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
namespace {

constexpr double MIB = 1024.0 * 1024.0;
constexpr double RUNTIME_BYTES = 48 * MIB;
constexpr double VDB_BYTES_PER_VOXEL = 4.5;
constexpr double VDB_LEAF = 8;  ///< voxels per leaf edge

std::string fmt(double value, int digits = 3) {
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
    // x-y tiles: core side (cells; 0 = one tile), count, the largest core and window, and the
    // windows' cells summed over the tiles (what the engine computes).
    double tileCells = 0, tiles = 1, coreCells = 0, windowCells = 0, computedCells = 0;
};

/// The exposure grid as stages.cpp's exposureGrid() will make it. The Monte Carlo kernel's
/// fitted radius is not known yet: scattering widens the beam, so the guess is 1.5 x w0.
void gridSizes(const Job& job, Sizes& s) {
    const bool mc = job.machine.process == plan::Process::Laser &&
                    job.kernel.source == kernel::KernelSource::MonteCarlo;
    s.beamRadius = job.machine.process == plan::Process::Laser &&
                           job.kernel.source == kernel::KernelSource::Given
                       ? job.kernel.given.radius
                       : job.machine.beamRadius * (mc ? 1.5 : 1.0);
    const SimulationSpec& sim = job.simulation;
    const double margin =
        sim.margin >= 0 ? sim.margin : 3.0 * std::max(s.beamRadius, job.machine.beamRadius);
    const glm::dvec3 size = s.bounds.size();
    s.nx = std::ceil((size.x + 2 * margin) / sim.voxel);
    s.ny = std::ceil((size.y + 2 * margin) / sim.voxel);
    s.cells = s.nx * s.ny;
    s.slices = double(s.layers) * sim.slicesPerLayer;
    s.voxels = s.cells * s.slices;
    s.voxelHeight = job.machine.layerThickness / sim.slicesPerLayer;
    // Stored: the part grown by the exposure's reach (1.5 W in x-y, where the Gaussian tail
    // falls under 2% of Ec; print-through a few attenuation lengths down) plus a leaf of
    // partial leaves on each side of the surface.
    const double depth = job.cure->hasPenetrationDepth() ? job.cure->penetrationDepth() : 0.0;
    const double reach =
        std::max(1.5 * s.beamRadius, 4.0 * depth) + VDB_LEAF * std::max(sim.voxel, s.voxelHeight);
    const double grown = s.volume + s.area * reach;
    s.activeVoxels = std::min(s.voxels, grown / (sim.voxel * sim.voxel * s.voxelHeight));
    s.surfaceVoxels = 2.0 * s.area / (sim.voxel * std::min(sim.voxel, s.voxelHeight));
}

/// Tiles of `side` mm (0: one) as stages.cpp's exposureTiles() lays them out; the halo is the
/// engine's reach plus the mesher's cell: the fitted blur's half-width (1.75 W, the radius
/// guessed as above), or for the tabulated engine its widest stencil, at most the kernel table's
/// radius (the Monte Carlo has not run yet, so its bound).
void tileSizes(const Job& job, double side, Sizes& s) {
    const double pitch = job.simulation.voxel;
    const bool tabulated = job.kernel.tabulated && job.machine.process == plan::Process::Laser;
    const double reach =
        tabulated ? std::ceil(kernel::kernelTableRadius(job.machine.beamRadius) / pitch + 0.5)
                  : std::ceil(1.75 * s.beamRadius / pitch);
    const double halo = reach + 1;
    s.tileCells = side > 0 ? std::ceil(side / pitch - 1e-9) : 0;
    const double t = s.tileCells > 0 ? s.tileCells : std::max(s.nx, s.ny);
    const double across = std::ceil(s.nx / t), down = std::ceil(s.ny / t);
    s.tiles = across * down;
    const double coreX = std::min(t, s.nx), coreY = std::min(t, s.ny);
    s.coreCells = coreX * coreY;
    if (s.tiles == 1) {
        s.windowCells = s.computedCells = s.cells;
        return;
    }
    s.windowCells = std::min(s.nx, coreX + 2 * halo) * std::min(s.ny, coreY + 2 * halo);
    s.computedCells = std::min(s.nx + 2 * halo * (across - 1), across * (coreX + 2 * halo)) *
                      std::min(s.ny + 2 * halo * (down - 1), down * (coreY + 2 * halo));
}

Sizes sizesOf(const Job& job, const geometry::Mesh& part) {
    Sizes s;
    s.bounds = part.bounds();
    s.volume = std::abs(part.volume());
    s.area = part.area();
    geometry::SliceOptions slicing;
    slicing.layerThickness = job.machine.layerThickness;
    slicing.zStart = 0.0;
    s.layers = geometry::layerCount(part, slicing);
    s.contourVertices = contourVertexCount(part, s.layers, job.machine.layerThickness, 0.0, 0.5);
    gridSizes(job, s);
    return s;
}

void add(JobEstimate& e, std::string name, double bytes, Stage first, Stage last,
         std::string detail, std::string hint = "", bool perTile = false) {
    e.items.push_back(
        {std::move(name), bytes, first, last, std::move(detail), std::move(hint), perTile});
}

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

std::string gridText(const Job& job, const Sizes& s) {
    return fmt(s.nx) + " x " + fmt(s.ny) + " cells x " + fmt(s.slices) + " slices at " +
           fmt(job.simulation.voxel * 1e3) + " um x " + fmt(s.voxelHeight * 1e3) + " um";
}

const char* COARSER =
    "a coarser simulation.voxel, fewer simulation.slices_per_layer, thicker layers or a "
    "smaller part";

std::string tileText(const Sizes& s) {
    if (s.tiles == 1) return "";
    return ", per tile of " + fmt(s.tiles) + " (" + fmt(s.coreCells) + " cells and a halo)";
}

/// Whether the run keeps a picture of the cured surface (runJob: the report's figures and 3D
/// view).
bool keepsSurface(const SimulationSpec& sim) {
    return sim.writes("figures") || sim.writes("viewer");
}

/// Whether that picture is every cured vertex (a surface within the view's budget), not one
/// clustered as it is made (report::viewCell).
bool keepsEverySurfaceVertex(const Job& job, const Sizes& s) {
    return keepsSurface(job.simulation) &&
           report::viewCell(s.area, job.simulation.voxel, s.voxelHeight) == 0;
}

/// The surface voxels the report's picture keeps: all, or the clustered view's (about two of its
/// triangles each).
double pictureSurfaceVoxels(const Job& job, const Sizes& s) {
    if (!keepsSurface(job.simulation)) return 0;
    return keepsEverySurfaceVertex(job, s) ? s.surfaceVoxels : report::CURED_VIEW_BUDGET / 2.0;
}

void exposureTerms(const Job& job, const Sizes& s, JobEstimate& e) {
    const int n = job.simulation.slicesPerLayer;
    const std::string tiled = tileText(s);
    if (job.kernel.tabulated && job.machine.process == plan::Process::Laser) {
        // The kernel's depth (3/mua) is not known before the Monte Carlo run: at most every layer.
        const double inFlight = double(s.layers) * n + 1;
        add(e, "tabulated exposure engine", s.windowCells * 4.0 * inFlight, Stage::Expose,
            Stage::Expose,
            fmt(s.windowCells) + " cells x " + fmt(inFlight) + " slices in flight" + tiled,
            "a coarser simulation.voxel or kernel.use = fitted", true);
    } else {
        add(e, "exposure engine (2D grids)", s.windowCells * 4.0 * 5.0, Stage::Expose,
            Stage::Expose, fmt(s.windowCells) + " cells, 5 float grids" + tiled, COARSER, true);
    }
    if (job.simulation.writeVdb)
        add(e, "exposure dose volume (OpenVDB)",
            s.activeVoxels * VDB_BYTES_PER_VOXEL + s.coreCells * 32.0, Stage::Expose, Stage::Expose,
            fmt(s.activeVoxels) + " stored voxels of " + fmt(s.voxels) + " (" + gridText(job, s) +
                "), 4.5 B each, and an 8-slice buffer (only for simulation.write_vdb; tiles do "
                "not shrink it)",
            std::string(COARSER) + ", or simulation.outputs without exposure.vdb");
    add(e, "slice validation", s.coreCells * 12.0, Stage::Expose, Stage::Validate,
        "a reference raster and per-column arrays of " + fmt(s.coreCells) + " cells" + tiled,
        COARSER, true);
    if (job.machine.process == plan::Process::Laser && !job.kernel.tabulated)  // the review's
        add(e, "laser exposure error (from the slices)",  // masks, histograms, the figure's map
            s.coreCells * 2.0 + 2 * MIB + (job.simulation.writes("figures") ? s.cells * 4.0 : 0),
            Stage::Expose, Stage::Validate,
            "two masks of " + fmt(s.coreCells) + " cells" + tiled + ", a histogram per thread",
            COARSER, true);
    if (job.simulation.writes("figures"))
        add(e, "sections (pictures)",
            s.cells * 5.0 + s.nx * s.slices * 5.0 +
                double(report::layerSectionBytes(int(s.nx), int(s.ny), int(s.layers))),
            Stage::Expose, Stage::Validate,
            "an x-y map of " + fmt(s.cells) + " cells, an x-z section of " + fmt(s.slices) +
                " slices and the 3D page's per-layer sections",
            COARSER);
    add(e, "streaming cured-surface mesher", s.windowCells * 22.0, Stage::Expose, Stage::Cure,
        "two padded slices with cured flags and two layers of vertex indices of " +
            fmt(s.windowCells) + " cells" + tiled,
        COARSER, true);
    // Every vertex is kept only for the report's figures and 3D view of a surface within the
    // view's budget; otherwise the mesher holds two layers of vertices (at most one per cell, a
    // flat top face) and the deviations become running statistics
    // (validate::DeviationStatistics, two 1 MiB histograms).
    if (keepsEverySurfaceVertex(job, s))
        add(e, "cured-surface vertices and deviations", s.surfaceVoxels * 16.0, Stage::Expose,
            Stage::Validate, fmt(s.surfaceVoxels) + " vertices (the triangles stream to cured.stl)",
            COARSER);
    else
        add(e, "cured-surface vertices of two layers", s.windowCells * 2.0 * 16.0 + MIB,
            Stage::Expose, Stage::Cure,
            "at most one vertex per cell and layer" + tiled +
                "; the deviations are running statistics",
            COARSER, true);
    e.stageSeconds.emplace_back("expose", 15e-9 * s.computedCells * s.slices);
    e.stageSeconds.emplace_back("cure", 1e-7 * s.surfaceVoxels);  // the mesher runs in expose
}

void validateTerms(const Job& job, const geometry::Mesh& part, const Sizes& s, JobEstimate& e,
                   double& referenceVoxels) {
    geometry::LevelSetOptions options;  // as validateStage() builds the reference
    options.voxelSize = std::max(job.simulation.voxel, 0.02);
    options.halfWidthVoxels =
        std::ceil(std::max(0.25, 4.0 * job.machine.beamRadius) / options.voxelSize);
    // The deviations are exact distances through a BVH of the part's triangles; the level set
    // is built only to be written as reference.vdb.
    add(e, "part BVH (exact distances)", 400.0 * double(part.triangles.size()), Stage::Expose,
        Stage::Cure, fmt(double(part.triangles.size())) + " triangles");
    const SimulationSpec& sim = job.simulation;
    if (sim.writes("reference.vdb")) {
        const double bytes = geometry::LevelSet::estimateBytes(part, options);
        referenceVoxels = bytes / 32.0;
        add(e, "reference level set", bytes, Stage::Validate, Stage::Validate,
            "narrow band of " + fmt(referenceVoxels) + " voxels at " +
                fmt(options.voxelSize * 1e3) + " um (only for the output reference.vdb)",
            "a smaller part (the reference level set uses max(simulation.voxel, 20 um))");
    }
    // The report draws the top view and the 3D view from the cured surface's picture, which the
    // mesher keeps for it: every triangle (2 per surface voxel, 12 B) of a surface within the
    // view's budget, else the clusters (validate::SurfaceClusters: 64 B and a hash entry each,
    // one per two triangles) and their triangles. The report copies it into a mesh (vertices
    // 24 B, triangles 24 B) and encodes it for the viewer; the plotting library's images are a
    // few tens of MiB. Only for the outputs figures and viewer (simulation.outputs).
    const char* FEWER = "simulation.outputs without figures and viewer, or a smaller part";
    if (keepsSurface(sim)) {
        const double kept = pictureSurfaceVoxels(job, s);
        if (keepsEverySurfaceVertex(job, s))
            add(e, "cured triangles kept for the report", kept * 24.0, Stage::Expose,
                Stage::Validate, fmt(2 * kept) + " triangles", FEWER);
        else
            add(e, "cured surface's clustered picture", kept * (112.0 + 24.0), Stage::Expose,
                Stage::Validate, fmt(kept) + " clusters and " + fmt(2 * kept) + " triangles",
                FEWER);
        add(e, "report: cured mesh, 3D view data, pictures", kept * 120.0 + 32.0 * MIB,
            Stage::Validate, Stage::Validate,
            "a mesh copy and its encoded 3D view, and the picture buffers", FEWER);
    }
    e.stageSeconds.emplace_back("validate", 2e-8 * s.surfaceVoxels + 1e-7 * referenceVoxels);
}

void outputTerms(const Job& job, const geometry::Mesh& part, const Sizes& s,
                 const planners::PlanSize& plan, double referenceVoxels, JobEstimate& e) {
    auto out = [&e](std::string file, double bytes) { e.outputs.push_back({file, bytes}); };
    out("part.stl", 84.0 + 50.0 * part.triangles.size());
    if (job.machine.process == plan::Process::Laser &&
        job.kernel.source == kernel::KernelSource::MonteCarlo)
        out("kernel/ (kernel.json, figures)", 0.5 * MIB);
    out("plan.json", plan.fileBytes);
    const bool laser = job.machine.process == plan::Process::Laser;
    for (const auto& [name, exporter] : job.exporters) {
        const std::string file = exporter->defaultFileName();
        const bool cli = file.size() > 4 && file.compare(file.size() - 4, 4, ".cli") == 0;
        if (cli != laser) continue;  // it cannot express this process's plan
        out(file, cli ? plan.planBytes * 0.2 : plan.maskPixels + 4096.0 * s.layers);
    }
    if (e.planOnly) return;
    const SimulationSpec& sim = job.simulation;
    if (sim.writes("exposure.vdb")) out("exposure.vdb", s.activeVoxels * 4.2 + 4096.0);
    if (sim.writes("reference.vdb")) out("reference.vdb", referenceVoxels * 4.2 + 4096.0);
    if (sim.writes("cured.stl")) out("cured.stl", 84.0 + 50.0 * 2.0 * s.surfaceVoxels);
    if (sim.writes("figures"))
        out("pictures (*.png, *.svg)", s.nx * s.slices * 4.0 + s.cells * 4.0 + MIB);
    if (sim.writes("viewer")) out("3D view (viewer3d data and scripts)", 20.0 * s.surfaceVoxels);
    out("report.json, index.html", 0.2 * MIB);
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
        exposureTerms(job, s, e);
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
