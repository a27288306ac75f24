#include <algorithm>
#include <cmath>

#include "vpsim/geometry/level_set.h"
#include "vpsim/report/layer_sections.h"
#include "vpsim/report/viewer3d.h"

#include "estimate_sizes.h"

namespace vpsim::pipeline::estimate_detail {
namespace {

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

}  // namespace

void exposureTerms(const Job& job, const Sizes& s, bool gpuDriver, JobEstimate& e) {
    const int n = job.simulation.slicesPerLayer;
    const std::string tiled = tileText(s);
    if (tabulatedEngine(job)) {
        // The kernel's depth (3/mua) is not known before the Monte Carlo run: at most every layer;
        // and the deposit with its zero-bordered copy (the borders are the stencils' width, small
        // against a row).
        const double inFlight = double(s.layers) * n + 2;
        add(e, "tabulated exposure engine", s.windowCells * 4.0 * inFlight, Stage::Expose,
            Stage::Expose,
            fmt(s.windowCells) + " cells x " + fmt(inFlight) + " slices in flight" + tiled,
            "a coarser simulation.voxel or kernel.use = fitted", true);
    } else {
        add(e, "exposure engine (2D grids)", s.windowCells * 4.0 * 5.0, Stage::Expose,
            Stage::Expose, fmt(s.windowCells) + " cells, 5 float grids" + tiled, COARSER, true);
        if (gpuDriver)  // the shader's padded running deposit and its sums, in device memory
            add(e, "exposure shader buffers", s.windowCells * 4.0 * 2.0, Stage::Expose,
                Stage::Expose, fmt(s.windowCells) + " cells, 2 float grids" + tiled, COARSER, true);
    }
    // Measured on lavapipe (peak RSS against --backend cpu, less the driver's 64 MiB): compiling
    // the shader where Mesa's shader cache has not got it (a new grid or stencil shape) and holding
    // it, 83-99 MiB for the fitted engine, 139 MiB for the tabulated one (unrolled for its
    // stencils' shape; the default job's kernel); from the cache 30 and 90 MiB.
    if (gpuDriver)
        add(e, "exposure shader pipeline", (tabulatedEngine(job) ? 160 : 104) * MIB, Stage::Expose,
            Stage::Validate, "compiled once per run (LLVM, when not yet cached)",
            "--backend cpu (the CPU loops)");
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
    // emitQuads makes a layer's triangles row by row before it writes them (rowTriangles, whose
    // rows keep their capacity): a flat face is two triangles of three indices per cell. Without
    // this term the 20 mm block's peak RSS (576 MiB) was 17% above the estimate.
    add(e, "cured-surface triangles of one layer", s.windowCells * 2.0 * 12.0, Stage::Expose,
        Stage::Cure, "two per cell at a flat face, before they are written" + tiled, COARSER, true);
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
    // Per computed voxel on the 2-core reference machine, the slices' consumers included
    // (README "Large parts"): the fitted engine 4.0-4.4 ns (the 10 mm, 20 mm and 100 mm blocks:
    // 2.4 s, 16.7 s, 2000 s), the tabulated one 71 ns with the default job's Monte Carlo kernel
    // (22 stencils up to 21 cells each side on its 10 um grid: a 4 mm cylinder's expose stage,
    // 9.6e6 voxels in 0.68 s; 156 ns before the blocked CPU gather), 0.59 times that since its
    // rows dj and -dj are folded (0.51 -> 0.30 s on a faster 2-core machine); rounded up.
    e.stageSeconds.emplace_back("expose",
                                (tabulatedEngine(job) ? 50e-9 : 5e-9) * s.computedCells * s.slices);
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
    // Two triangles of 50 bytes a crossed edge. The cured surface is rougher than the model's:
    // a laser part's (the hatch's ripple) had 1.16-1.55 times the triangles on the examples and
    // 1.7 on the estimate test's inverse plan at 5 um, a DLP part's 0.99-1.06.
    const double rough = job.machine.process == plan::Process::Laser ? 1.8 : 1.25;
    if (sim.writes("cured.stl")) out("cured.stl", 84.0 + 50.0 * 2.0 * rough * s.surfaceEdges);
    if (sim.writes("figures"))
        out("pictures (*.png, *.svg)", s.nx * s.slices * 4.0 + s.cells * 4.0 + MIB);
    // mesh3d.js: 7.2 MB for the 273k triangles of the block's clustered picture; three.js 1 MB.
    if (sim.writes("viewer"))
        out("3D view (viewer3d data and scripts)", 32.0 * pictureSurfaceVoxels(job, s) + MIB);
    out("report.json, index.html", 0.2 * MIB);
    // A tiled run checkpoints after each tile (pipeline/checkpoint.h): the pictures' state of
    // the figures and the 3D view goes to a binary file, two of them while one replaces the
    // other; the run removes them at its end (the cured STL grows in place: counted above).
    if (s.tiles > 1 && !sim.writes("exposure.vdb") && keepsSurface(sim)) {
        double pictures = 76.0 * pictureSurfaceVoxels(job, s);  // 64 B a cluster, 12 a triangle
        if (sim.writes("figures"))  // the sections' maps and the exposure-error map
            pictures += s.cells * 9.0 + s.nx * s.slices * 5.0;
        if (sim.writes("viewer"))
            pictures += double(report::layerSectionBytes(int(s.nx), int(s.ny), int(s.layers)));
        out("checkpoint/pictures-N.bin (while the run lasts)", 2.0 * pictures);
    }
}

}  // namespace vpsim::pipeline::estimate_detail
