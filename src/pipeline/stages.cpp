#include "vpsim/pipeline/stages.h"

#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/core/text.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/exposure/tabulated_engine.h"
#include "vpsim/geometry/level_set.h"
#include "vpsim/geometry/part_spec.h"
#include "vpsim/gpu/context.h"
#include "vpsim/kernel/kernel_cache.h"
#include "vpsim/validate/streaming_surface.h"
#include "vpsim/validate/surface_deviation.h"

namespace vpsim::pipeline {

geometry::Mesh partStage(const Job& job) {
    return geometry::loadPart(job.part);
}

namespace {

/// The beam of one kernel spec: given, or the material's Monte Carlo kernel (cached) and its fit.
kernel::FittedBeam laserBeam(const Job& job, const kernel::KernelSpec& spec,
                             const RunContext& context, std::optional<kernel::BeamKernel>& table,
                             bool& fromCache) {
    if (spec.source == kernel::KernelSource::Given) return spec.given;
    kernel::KernelRequest request = kernel::kernelRequest(
        job.materialFile, job.machine.laserPower, job.machine.beamRadius, spec.photons, spec.seed);
    request.setup.estimator = spec.estimator;
    table = kernel::cachedKernel(request, context, fromCache);
    return kernel::fittedBeamOf(*table);
}

}  // namespace

BeamResult beamStage(const Job& job, const RunContext& context) {
    BeamResult result;
    if (job.machine.process == plan::Process::Dlp) {
        result.beam.radius = job.machine.beamRadius;
        result.beam.attenuationLength = job.cure->penetrationDepth();
        return result;
    }
    result.beam = laserBeam(job, job.kernel, context, result.monteCarlo, result.fromCache);
    if (job.kernel.plan)
        result.planBeam =
            laserBeam(job, *job.kernel.plan, context, result.planMonteCarlo, result.planFromCache);
    return result;
}

geometry::LayerStack sliceStage(const Job& job, const geometry::Mesh& part) {
    // A layer thicker than the part leaves no slicing plane inside it: zero layers, and every
    // later stage would index an empty stack.
    const double height = part.bounds().hi.z;
    if (!(job.machine.layerThickness <= height))
        throw InputError("layer thickness " + formatQuantity(job.machine.layerThickness) +
                             " mm is more than the part's height " + formatQuantity(height) +
                             " mm: no layer to print",
                         job.file, "machine.layer_thickness");
    geometry::SliceOptions options;
    options.layerThickness = job.machine.layerThickness;
    options.zStart = 0.0;
    return geometry::sliceToStack(part, options, job.part.source());
}

PlanResult planStage(const Job& job, const geometry::LayerStack& layers,
                     const geometry::Bounds& partBounds, const BeamResult& beam,
                     const RunContext& context, const geometry::Mesh* part) {
    const kernel::BeamKernel* table =
        job.kernel.tabulated && beam.monteCarlo ? &*beam.monteCarlo : nullptr;
    if (job.kernel.plan)  // the planner sees the planning kernel only
        table = job.kernel.plan->tabulated && beam.planMonteCarlo ? &*beam.planMonteCarlo : nullptr;
    planners::PlannerInputs inputs{
        layers,    partBounds, job.machine, beam.planningBeam(), table, job.cure->criticalDose(),
        *job.cure, context,    part};
    PlanResult result;
    result.plan = job.planner->plan(inputs);
    result.summary = job.planner->summary();
    return result;
}

void checkPlanFitsJob(const plan::ScanPlan& plan, const Job& job,
                      const geometry::LayerStack& layers, const std::string& file) {
    if (plan.machine.process != job.machine.process)
        throw InputError("the plan is for a " + plan::processName(plan.machine.process) +
                             " machine, the job's is " + plan::processName(job.machine.process),
                         file, "machine.process");
    if (std::abs(plan.machine.layerThickness - job.machine.layerThickness) >
        1e-9 * job.machine.layerThickness)
        throw InputError("the plan's layer thickness differs from the job's (" +
                             formatQuantity(job.machine.layerThickness) + " mm)",
                         file, "machine.layer_thickness");
    if (plan.layers.size() != layers.layers.size())
        throw InputError("the plan has " + std::to_string(plan.layers.size()) +
                             " layers, the job's part has " + std::to_string(layers.layers.size()),
                         file, "layers");
}

std::vector<std::string> exportStage(const Job& job, const plan::ScanPlan& plan,
                                     const std::string& outDir) {
    std::vector<std::string> written;
    for (const auto& [name, exporter] : job.exporters) {
        std::string reason;
        if (!exporter->accepts(plan, reason)) {
            logInfo("export " + name + " skipped: " + reason);
            continue;
        }
        exporter->write(plan, outDir + "/" + exporter->defaultFileName());
        written.push_back(exporter->defaultFileName());
    }
    return written;
}

exposure::ExposureGrid exposureGrid(const Job& job, const geometry::Bounds& b,
                                    const BeamResult& beam) {
    const SimulationSpec& sim = job.simulation;
    double margin =
        sim.margin >= 0 ? sim.margin : 3.0 * std::max(beam.beam.radius, job.machine.beamRadius);
    return exposure::ExposureGrid::covering(b.lo.x, b.lo.y, b.hi.x, b.hi.y, margin, sim.voxel,
                                            sim.slicesPerLayer);
}

std::unique_ptr<exposure::ExposureModel> exposureModel(const Job& job,
                                                       const exposure::ExposureGrid& grid,
                                                       const BeamResult& beam,
                                                       const RunContext& context) {
    // The shaders on every Vulkan device, lavapipe included (RunContext::gpu).
    const std::shared_ptr<gpu::Context>& gpu = context.gpu;
    const double h = job.machine.layerThickness;
    if (job.kernel.tabulated && beam.monteCarlo)
        return std::make_unique<exposure::TabulatedExposureEngine>(grid, *beam.monteCarlo, h, gpu);
    return std::make_unique<exposure::ExposureEngine>(grid, beam.beam, h, gpu);
}

std::vector<exposure::Tile> exposureTiles(const exposure::ExposureModel& model, double tileSide) {
    const exposure::ExposureGrid& g = model.grid();
    const int cells = tileSide > 0 ? std::max(1, int(std::ceil(tileSide / g.pitch - 1e-9))) : 0;
    return exposure::tileLayout(g, cells, model.reachCells() + 1);
}

report::ExposureSummary exposeStage(const Job& job, exposure::ExposureModel& model,
                                    const std::vector<exposure::Tile>& tiles,
                                    const plan::ScanPlan& plan,
                                    const std::vector<exposure::SliceSink>& consumers,
                                    const BeamResult& beam, int layers, const RunContext& context,
                                    int firstTile, const TileDone& afterTile) {
    report::ExposureSummary summary;
    double sinkSeconds = 0;
    auto sink = [&](const exposure::ExposureSlice& slice) {
        auto start = std::chrono::steady_clock::now();
        // The consumers keep states of their own and only read the slice: side by side, one
        // fills the cores while another is in a serial part (the mesher's numbering, its STL).
        tbb::parallel_for(size_t(0), consumers.size(), [&](size_t c) { consumers[c](slice); });
        sinkSeconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    if (tiles.size() == 1) {
        summary.engineSeconds = model.run(plan, sink);
    } else {
        for (const exposure::Tile& tile : tiles) {
            if (tile.index < firstTile) continue;  // done before a resumed run
            logInfo("tile " + std::to_string(tile.index + 1) + " of " +
                    std::to_string(tiles.size()) + ": cells [" + std::to_string(tile.core.i0) +
                    ", " + std::to_string(tile.core.i1) + ") x [" + std::to_string(tile.core.j0) +
                    ", " + std::to_string(tile.core.j1) + ")");
            auto tileModel = exposureModel(job, model.grid().window(tile.window), beam, context);
            summary.engineSeconds += tileModel->run(plan, tile.core, sink);
            if (afterTile) afterTile(tile);
        }
    }
    const exposure::ExposureGrid& g = model.grid();
    summary.model = model.name();
    summary.backend = model.usesGpu() ? "gpu" : "cpu";
    summary.grid[0] = g.nx;
    summary.grid[1] = g.ny;
    summary.grid[2] = layers * g.slicesPerLayer;
    summary.voxel[0] = summary.voxel[1] = g.pitch;
    summary.voxel[2] = model.layerThickness() / g.slicesPerLayer;
    summary.sinkSeconds = sinkSeconds;
    summary.beam = beam.beam;
    return summary;
}

namespace {

geometry::LevelSetOptions referenceOptions(const Job& job) {
    // The reference needs a band as wide as the deviations it measures (up to a few beam radii,
    // 0.25 mm at least: print-through over-cure), but not the exposure's voxel.
    geometry::LevelSetOptions options;
    options.voxelSize = std::max(job.simulation.voxel, 0.02);
    options.halfWidthVoxels =
        std::ceil(std::max(0.25, 4.0 * job.machine.beamRadius) / options.voxelSize);
    return options;
}

}  // namespace

double deviationBand(const Job& job) {
    const geometry::LevelSetOptions options = referenceOptions(job);
    return options.halfWidthVoxels * options.voxelSize;
}

std::unique_ptr<validate::StreamingCuredSurface> curedSurfaceSink(
    const Job& job, const exposure::ExposureGrid& grid, double voxelHeight,
    const geometry::Mesh& part, const std::string& stlPath, bool inPlace) {
    if (inPlace && !stlPath.empty())
        return std::make_unique<validate::StreamingCuredSurface>(
            grid, voxelHeight, job.cure->criticalDose(), &part, deviationBand(job),
            validate::StreamingCuredSurface::InPlaceStl{stlPath});
    return std::make_unique<validate::StreamingCuredSurface>(
        grid, voxelHeight, job.cure->criticalDose(), &part, deviationBand(job), stlPath);
}

void cureStage(validate::StreamingCuredSurface& cured) {
    cured.finish();
}

report::ValidationReport validateStage(const Job& job, const geometry::Mesh& part,
                                       const validate::StreamingCuredSurface& cured,
                                       validate::SliceValidationSummary slices,
                                       validate::FeatureMeasurements features,
                                       const std::string& referenceVdb) {
    if (!referenceVdb.empty())
        geometry::LevelSet::fromMesh(part, referenceOptions(job)).save(referenceVdb);
    report::ValidationReport report;
    report.deviationStatistics = cured.statistics();
    report.deviation = report.deviationStatistics.summary();
    report.slices = std::move(slices);
    report.features = std::move(features);
    return report;
}

}  // namespace vpsim::pipeline
