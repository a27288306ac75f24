#include "vpsim/report/run_job.h"

#include <chrono>
#include <cmath>
#include <functional>
#include <optional>

#include <nlohmann/json.hpp>

#include "report/figures.h"
#include "report/html_report.h"
#include "report/kernel_cache.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/log.h"
#include "vpsim/exposure/dose_volume.h"
#include "vpsim/exposure/tabulated_engine.h"
#include "vpsim/geometry/level_set.h"
#include "vpsim/geometry/slicer.h"
#include "vpsim/geometry/stl_io.h"
#include "vpsim/gpu/context.h"
#include "vpsim/plan/aces.h"
#include "vpsim/plan/dlp_masks.h"
#include "vpsim/validate/surface_deviation.h"

namespace vpsim::report {
namespace {

/// Wall-clock seconds of each stage, logged as it finishes.
class StageTimer {
public:
    void finish(const std::string& stage) {
        auto now = std::chrono::steady_clock::now();
        double seconds = std::chrono::duration<double>(now - mStart).count();
        mSeconds[stage] = seconds;
        logInfo("stage " + stage + ": " + std::to_string(seconds).substr(0, 6) + " s");
        mStart = now;
    }
    const nlohmann::json& seconds() const { return mSeconds; }

private:
    std::chrono::steady_clock::time_point mStart = std::chrono::steady_clock::now();
    nlohmann::json mSeconds = nlohmann::json::object();
};

geometry::Mesh loadPart(const Job& job) {
    geometry::Mesh part;
    if (!job.partStl.empty()) {
        geometry::StlReadOptions options;
        options.scale = job.partScale;
        part = geometry::readStl(job.partStl, options);
    } else {
        part = geometry::makeTestPart(job.testPart, job.testPartOptions);
    }
    part.translate({0, 0, -part.bounds().lo.z});  // the build platform is z = 0
    return part;
}

/// The separable beam the engine uses, and the depth of the sub-surface maximum (mm).
kernel::FittedBeam beamOf(const Job& job, const std::string& outDir,
                               const std::shared_ptr<gpu::Context>& context, double& zmax,
                               std::optional<kernel::BeamKernel>& table, nlohmann::json& report) {
    kernel::FittedBeam beam;
    zmax = 0;
    if (job.process == Process::Dlp) {
        if (!(job.cure.penetrationDepth() > 0))
            throw InputError(
                "a DLP job needs the resin's penetration depth (cure.penetration_depth or "
                "cure.attenuation)",
                job.file, "cure");
        beam.radius = job.beamRadius;
        beam.attenuationLength = job.cure.penetrationDepth();
    } else if (job.kernelSource == KernelSource::Given) {
        beam = {job.givenWe3d, job.givenDe3d, job.givenZmax, job.givenEfficiency};
        zmax = job.givenZmax;
    } else {
        bool cached = false;
        kernel::BeamKernel k = monteCarloKernel(job, context, cached);
        createDirectories(outDir + "/kernel");
        k.save(outDir + "/kernel/kernel.json");
        kernel::writeKernelFigures(outDir + "/kernel", k);
        beam.radius = k.fit.we3d;
        beam.attenuationLength = k.fit.de3d;
        beam.efficiency = k.fit.amplitude * M_PI * k.fit.we3d * k.fit.we3d / (2.0 * job.laserPower);
        zmax = k.zmax;
        if (job.tabulatedKernel) table = k;
        report["kernel"] = {{"We3D_um", k.fit.we3d * 1e3},
                            {"De3D_um", k.fit.de3d * 1e3},
                            {"zmax_um", k.zmax * 1e3},
                            {"fit_residual", k.fit.residual},
                            {"efficiency", beam.efficiency},
                            {"photons", k.photons},
                            {"from_cache", cached},
                            {"exposure_uses", job.tabulatedKernel ? "table" : "fit"}};
    }
    return beam;
}

plan::ScanPlan planLayers(const Job& job, const std::vector<geometry::Layer>& layers,
                          const kernel::FittedBeam& beam, double zmax,
                          const geometry::Bounds& bounds, nlohmann::json& report) {
    plan::ScanPlan plan;
    plan.machine.layerThickness = job.layerThickness;
    plan.machine.laserPower = job.laserPower;
    plan.machine.beamRadius = job.beamRadius;
    plan.machine.pixelPitch = job.pixelPitch;
    geometry::RasterGrid projector = geometry::RasterGrid::covering(
        {bounds.lo.x, bounds.lo.y}, {bounds.hi.x, bounds.hi.y}, job.pixelPitch, 2);
    plan::AcesParameters aces;
    aces.beamRadius = beam.radius;
    aces.attenuationLength = beam.attenuationLength;
    aces.depthOfMaximum = std::min(zmax, 0.99 * job.layerThickness);
    aces.criticalDose =
        job.cure.criticalDose() / beam.efficiency;  // Etar is asked of the delivered dose
    aces.layerThickness = job.layerThickness;
    aces.laserPower = job.laserPower;
    aces.homogeneity = job.homogeneity;
    aces.edge =
        job.edgeFivePercent ? plan::AcesEdge::SeedFivePercent : plan::AcesEdge::CureAtContour;
    for (const auto& layer : layers) {
        double top = layer.zBottom + job.layerThickness;
        if (layer.region.empty()) {
            plan.layers.push_back({top, {}, {}, {}});
            continue;
        }
        if (job.strategy == PlanStrategy::Aces) {
            plan::AcesDesign design = plan::designAces(aces, layer.region);
            plan.layers.push_back(plan::planAcesLayer(layer.region, design, job.laserPower, top));
            if (!report.contains("aces"))
                report["aces"] = {
                    {"target_dose_mJ_per_cm2", design.targetDose * beam.efficiency * 100},
                    {"hatch_spacing_um", design.hatchSpacing * 1e3},
                    {"speed_mm_per_s", design.speed},
                    {"edge_offset_um", design.edgeOffset * 1e3},
                    {"ripple", design.ripple}};
        } else {
            plan::LayerPlan lp;
            lp.z = top;
            lp.masks.push_back(plan::uniformMask(layer.region, projector, job.maskDose,
                                                 job.greyscaleMask ? plan::MaskRasterMode::Greyscale
                                                                   : plan::MaskRasterMode::Binary));
            plan.layers.push_back(std::move(lp));
        }
    }
    report["plan"] = {{"layers", plan.layers.size()}, {"energy_mJ", plan.totalEnergy()}};
    return plan;
}

}  // namespace

nlohmann::json runJob(const Job& job, const std::string& outDir,
                      const std::shared_ptr<gpu::Context>& context,
                      bool exposureShadersOnCpuDevices) {
    createDirectories(outDir);
    StageTimer timer;
    nlohmann::json report{{"job", job.file},
                          {"name", job.name},
                          {"backend", context ? context->info().name : std::string("cpu")},
                          {"cure", job.cure.toJson()}};

    geometry::Mesh part = loadPart(job);
    geometry::writeStl(outDir + "/part.stl", part);
    geometry::Bounds bounds = part.bounds();
    report["part"] = {{"volume_mm3", part.volume()},
                      {"size_mm", {bounds.size().x, bounds.size().y, bounds.size().z}},
                      {"triangles", part.triangles.size()}};
    timer.finish("part");

    double zmax = 0;
    std::optional<kernel::BeamKernel> table;
    kernel::FittedBeam beam = beamOf(job, outDir, context, zmax, table, report);
    timer.finish("kernel");

    geometry::SliceOptions sliceOptions;
    sliceOptions.layerThickness = job.layerThickness;
    sliceOptions.zStart = 0.0;
    std::vector<geometry::Layer> layers = geometry::sliceMesh(part, sliceOptions);
    timer.finish("slice");

    plan::ScanPlan plan = planLayers(job, layers, beam, zmax, bounds, report);
    plan::saveScanPlan(plan, outDir + "/plan.json");
    timer.finish("plan");

    double margin = job.margin >= 0 ? job.margin : 3.0 * std::max(beam.radius, job.beamRadius);
    exposure::ExposureGrid grid = exposure::ExposureGrid::covering(
        bounds.lo.x, bounds.lo.y, bounds.hi.x, bounds.hi.y, margin, job.voxel, job.slicesPerLayer);
    const double voxelHeight = job.layerThickness / job.slicesPerLayer,
                 ec = job.cure.criticalDose();
    // The fitted kernel runs in the separable engine, the tabulated one in the depth-sliced
    // convolution engine; both in compute shaders when there is a context, else on the CPU.
    std::function<double(const plan::ScanPlan&, const exposure::SliceSink&)> expose;
    std::shared_ptr<gpu::Context> exposureContext =
        context && (context->info().isHardware() || exposureShadersOnCpuDevices) ? context
                                                                                 : nullptr;
    if (table) {
        auto engine = std::make_shared<exposure::TabulatedExposureEngine>(
            grid, *table, job.layerThickness, exposureContext);
        expose = [engine](const plan::ScanPlan& p, const exposure::SliceSink& sink) {
            return engine->run(p, sink);
        };
    } else {
        auto engine = std::make_shared<exposure::ExposureEngine>(grid, beam, job.layerThickness,
                                                                 exposureContext);
        expose = [engine](const plan::ScanPlan& p, const exposure::SliceSink& sink) {
            return engine->run(p, sink);
        };
    }
    exposure::DoseVolume volume(grid, voxelHeight, 0.0, float(0.02 * ec));
    validate::SliceValidator validator(part, grid, ec, voxelHeight);
    const int middle = int(layers.size()) / 2;
    SectionRecorder sections(part, grid, int(layers.size()) * job.slicesPerLayer, ec, middle,
                             busiestRow(layers[middle].region, grid));
    validate::FeatureProbes features(job.features, grid, ec, voxelHeight);
    double sinkSeconds = 0;
    double engineSeconds = expose(plan, [&](const exposure::ExposureSlice& slice) {
        auto start = std::chrono::steady_clock::now();
        volume.add(slice);
        validator.add(slice);
        sections.add(slice);
        features.add(slice);
        sinkSeconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    });
    report["exposure"] = {
        {"backend", exposureContext ? exposureContext->info().name : std::string("cpu")},
        {"grid", {grid.nx, grid.ny, int(layers.size()) * job.slicesPerLayer}},
        {"voxel_um", {job.voxel * 1e3, job.voxel * 1e3, voxelHeight * 1e3}},
        {"engine_seconds", engineSeconds},
        {"store_and_compare_seconds", sinkSeconds},
        {"max_mJ_per_cm2", volume.maxValue() * 100.0},
        {"stored_voxels", volume.activeVoxels()},
        {"beam",
         {{"We3D_um", beam.radius * 1e3},
          {"De3D_um", beam.attenuationLength * 1e3},
          {"efficiency", beam.efficiency}}}};
    if (job.writeVdb) volume.write(outDir + "/exposure.vdb");
    timer.finish("expose");

    geometry::Mesh cured = volume.isosurface(float(ec));
    if (cured.triangles.empty())
        throw InputError("nothing cured: the exposure never reaches the critical dose", job.file);
    geometry::writeStl(outDir + "/cured.stl", cured);
    report["cured_volume_mm3"] = cured.volume();
    timer.finish("cure");

    validate::SliceValidationSummary slices = validator.summary();
    // The reference distance field needs a band as wide as the deviations it measures (up to a
    // few beam radii, 0.25 mm at least: print-through over-cure), but not the exposure's voxel:
    // trilinear interpolation of an exact distance field is accurate to a small part of its voxel.
    geometry::LevelSetOptions levelSetOptions;
    levelSetOptions.voxelSize = std::max(job.voxel, 0.02);
    levelSetOptions.halfWidthVoxels =
        std::ceil(std::max(0.25, 4.0 * job.beamRadius) / levelSetOptions.voxelSize);
    geometry::LevelSet reference = geometry::LevelSet::fromMesh(part, levelSetOptions);
    if (job.writeVdb) reference.save(outDir + "/reference.vdb");
    std::vector<float> deviations = validate::vertexDeviations(cured, reference);
    validate::SurfaceDeviation deviation =
        validate::summarizeDeviations(deviations, reference.halfWidth());
    report["iou"] = slices.iou;
    report["surface_deviation_mm"] = deviation.toJson();
    report["overcure_below_downfacing_mm"] = slices.overcureBelowDownFacingMedian;
    report["validation"] = slices.toJson();
    if (!job.features.empty()) report["features"] = features.toJson();
    timer.finish("validate");

    sections.write(outDir);
    writeDeviationFigures(outDir, cured, deviations);
    writeLayerErrorPlot(outDir + "/xy_error_per_layer.svg", slices);
    timer.finish("report");
    report["stage_seconds"] = timer.seconds();
    writeFileAtomic(outDir + "/report.json", report.dump(2));
    writeHtmlReport(outDir, report);
    return report;
}

}  // namespace vpsim::report
