#include "vpsim/pipeline/run_job.h"

#include <filesystem>

#include "vpsim/cluster/communicator.h"
#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/log.h"
#include "vpsim/core/output_directory.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/text.h"
#include "vpsim/exposure/dose_volume.h"
#include "vpsim/geometry/stl_io.h"
#include "vpsim/gpu/context.h"
#include "vpsim/pipeline/checkpoint.h"
#include "vpsim/pipeline/cluster_run.h"
#include "vpsim/pipeline/estimate.h"
#include "vpsim/pipeline/picture_recorders.h"
#include "vpsim/planners/laser_exposure_review.h"
#include "vpsim/plot/plot.h"
#include "vpsim/report/deviation_map.h"
#include "vpsim/report/figures.h"
#include "vpsim/report/html_report.h"
#include "vpsim/report/layer_sections.h"
#include "vpsim/report/viewer3d.h"
#include "vpsim/validate/feature_probe.h"
#include "vpsim/validate/slice_validator.h"
#include "vpsim/validate/streaming_surface.h"

#include "stage_timer.h"

namespace vpsim::pipeline {
namespace {

/// The job file and its material as written, for the report's inputs (both were read and
/// checked by loadJob, under its limits).
nlohmann::json jobInputs(const Job& job) {
    nlohmann::json material;  // read and checked when the kernel was computed
    if (!job.materialFile.empty()) {
        try {
            material = loadJsonFile(job.materialFile);
        } catch (const InputError&) {}
    }
    return {{"job", job.document}, {"material", material}};
}

std::string deviceName(const RunContext& context) {
    return context.gpu ? context.gpu->info().name : std::string("cpu");
}

/// The front of a run: part, beam and layers, each saved.
struct Front {
    geometry::Mesh part;
    geometry::Bounds bounds;
    BeamResult beam;
    geometry::LayerStack layers;
};

/// The part, checked against the layer thickness before anything is written or the kernel is
/// computed (sliceStage checks it too).
geometry::Mesh checkedPart(const Job& job) {
    geometry::Mesh part = partStage(job);
    if (!(job.machine.layerThickness <= part.bounds().hi.z))
        throw InputError("layer thickness " + formatQuantity(job.machine.layerThickness) +
                             " mm is more than the part's height " +
                             formatQuantity(part.bounds().hi.z) + " mm: no layer to print",
                         job.file, "machine.layer_thickness");
    return part;
}

Front runFront(const Job& job, geometry::Mesh part, const std::string& outDir,
               const RunContext& context, report::JobResult& result, StageTimer& timer) {
    Front f;
    f.part = std::move(part);
    createDirectories(outDir);
    geometry::writeStl(outDir + "/part.stl", f.part);
    f.bounds = f.part.bounds();
    result.part = {f.part.volume(),
                   {f.bounds.size().x, f.bounds.size().y, f.bounds.size().z},
                   f.part.triangles.size()};
    timer.finish("part");

    f.beam = beamStage(job, context);
    result.mpi = clusterSummary(f.beam, context);
    if (f.beam.monteCarlo) {
        const kernel::BeamKernel& k = *f.beam.monteCarlo;
        createDirectories(outDir + "/kernel");
        k.save(outDir + "/kernel/kernel.json");
        if (job.simulation.writes("figures")) kernel::writeKernelFigures(outDir + "/kernel", k);
        report::KernelSummary summary;
        summary.beam = f.beam.beam;
        summary.fitResidual = k.fit.residual;
        summary.fitEnergyFraction = k.fit.energyFraction;
        summary.estimator = transport::estimatorName(job.kernel.estimator);
        summary.photons = k.photons;
        summary.fromCache = f.beam.fromCache;
        summary.tabulatedExposure = job.kernel.tabulated;
        result.kernel = summary;
    }
    timer.finish("kernel");

    f.layers = sliceStage(job, f.part);
    timer.finish("slice");
    return f;
}

/// What planning with `kernel.plan` instead of the simulated kernel costs: both kernels, the
/// run's figures and, unless the plan was a saved one, the slice figures of the plan the same
/// planner makes with the simulated kernel, exposed on the same model.
nlohmann::json kernelMismatch(const Job& job, const Front& f, exposure::ExposureModel& model,
                              const report::ValidationReport& run, bool saved,
                              const RunContext& context) {
    nlohmann::json out = {
        {"planning_kernel", f.beam.planBeam->toJson()},
        {"simulated_kernel", f.beam.beam.toJson()},
        {"note", "planned with kernel.plan; exposed, cured and validated with the job's kernel"},
        {"iou", run.slices.iou},
        {"surface_deviation_mm", {{"mean", run.deviation.mean}, {"rms", run.deviation.rms}}},
        {"overcure_below_downfacing_mean_mm", run.slices.overcureBelowDownFacingMean},
        {"xy_contour_error_mean_mm", run.slices.xyContourErrorMean}};
    if (saved) return out;
    BeamResult matched = f.beam;  // the simulated kernel for the planner too
    matched.planBeam.reset();
    matched.planMonteCarlo.reset();
    const plan::ScanPlan plan = planStage(job, f.layers, f.bounds, matched, context, &f.part).plan;
    const double voxelHeight = job.machine.layerThickness / job.simulation.slicesPerLayer;
    validate::SliceValidator validator(f.part, model.grid(), *job.cure, voxelHeight);
    model.run(plan, [&](const exposure::ExposureSlice& s) { validator.add(s); });
    const validate::SliceValidationSummary m = validator.summary();
    out["matched_plan"] = {{"iou", m.iou},
                           {"overcure_below_downfacing_mean_mm", m.overcureBelowDownFacingMean},
                           {"xy_contour_error_mean_mm", m.xyContourErrorMean}};
    out["iou_cost"] = m.iou - run.slices.iou;
    return out;
}

/// A tile's share of cured.stl by the estimate: its average over the tiles, which the largest
/// tile's share is at least, so a rank without that much room cannot keep its tiles' triangles.
double tileStlShare(const JobEstimate& estimate) {
    for (const OutputEstimate& output : estimate.outputs)
        if (output.file == "cured.stl") return output.bytes / std::max(1, estimate.tileCount);
    return 0;
}

}  // namespace

PlanResult planJob(const Job& job, const std::string& outDir, const RunContext& context) {
    geometry::Mesh part = checkedPart(job);
    checkEstimate(estimateJob(job, part, true, false, context.gpu != nullptr),
                  context);  // before the kernel or anything written
    if (job.simulation.writes("figures")) plot::requirePlotting();
    // Removes the previous manifest and dead runs' temporaries; manifest.json is written last.
    OutputDirectory output(outDir,
                           {{"command", "plan"}, {"job", job.name}, {"job_file", job.file}});
    report::JobResult result;
    StageTimer timer(result.stageSeconds);
    Front f = runFront(job, std::move(part), outDir, context, result, timer);
    PlanResult plan = planStage(job, f.layers, f.bounds, f.beam, context, &f.part);
    scanStage(job, f.layers, plan.plan);  // the plan is saved with its trajectories
    plan::saveScanPlan(plan.plan, outDir + "/plan.json");
    exportStage(job, plan.plan, outDir);
    timer.finish("plan");
    output.finish();
    return plan;
}

report::JobResult runJob(const Job& job, const std::string& outDir, const RunContext& context,
                         const RunOptions& options) {
    // A saved plan is read before anything in outDir is replaced (it may live there).
    std::optional<plan::ScanPlan> saved;
    if (!options.planFile.empty()) saved = plan::loadScanPlan(options.planFile);
    geometry::Mesh part = checkedPart(job);
    // The x-y tiles are chosen here to fit the budget; what no tiling fits is refused.
    const JobEstimate estimate =
        fitEstimate(job, part, context, false, saved.has_value(), context.gpu != nullptr);
    checkEstimate(estimate, context);
    checkDisk(estimate, outDir);
    if (job.simulation.writes("figures")) plot::requirePlotting();
    const double tileSide = estimate.tileSide;
    // From here the directory is untrusted until manifest.json, written last, lists every file
    // of this run with its size and SHA-256 (core/output_directory.h).
    const auto runStart = std::filesystem::file_time_type::clock::now();
    OutputDirectory output(outDir, {{"command", "run"}, {"job", job.name}, {"job_file", job.file}});
    // A changed input file (the material, the part's STL) makes the checkpoint another job's.
    const std::string inputs = jobInputsFingerprint(job);
    std::optional<TileCheckpoint> checkpoint;
    if (options.resume)
        checkpoint = loadCheckpoint(outDir, inputs);
    else
        removeCheckpoint(outDir);  // a fresh run starts over

    report::JobResult result;
    result.jobFile = job.file;
    result.name = job.name;
    result.backend = deviceName(context);
    result.cure = job.cure->toJson();
    StageTimer timer(result.stageSeconds);
    Front f = runFront(job, std::move(part), outDir, context, result, timer);

    PlanResult planned;
    // A resumed run exposes the plan it was exposing (planning again may take minutes, and a
    // planner need not repeat itself bit for bit), unless the planner's review needs what its
    // planning kept besides the plan.
    const bool planResumed = checkpoint && !saved && !job.planner->reviewNeedsPlanning();
    if (saved) {
        checkPlanFitsJob(*saved, job, f.layers, options.planFile);
        planned.plan = std::move(*saved);
    } else if (planResumed) {
        planned.plan = checkpointPlan(*checkpoint, outDir);
        planned.summary = checkpoint->planReport;
        logInfo("--resume: exposing the checkpoint's plan (" + outDir +
                "/plan.json, its SHA-256 checked), not planning again");
    } else {
        planned = planStage(job, f.layers, f.bounds, f.beam, context, &f.part);
    }
    result.plan = {job.strategy, planned.plan.layers.size(), planned.plan.totalEnergy(),
                   planned.summary};
    if (planResumed) {  // scanned and saved by the interrupted run, with its report figures
        output.record("plan.json");
    } else {
        const plan::ScanSchedule schedule = scanStage(job, f.layers, planned.plan);
        plan::saveScanPlan(planned.plan, outDir + "/plan.json");
        writeScanFiles(schedule, planned.plan, outDir, job.simulation.writes("figures"));
        addScheduleFigures(schedule, result.plan.planner);
    }
    if (saved) result.plan.strategy = "saved plan " + options.planFile;
    timer.finish("plan");
    result.exports = exportStage(job, planned.plan, outDir);
    timer.finish("export");
    const int layers = int(f.layers.layers.size());
    const exposure::ExposureGrid grid = exposureGrid(job, f.bounds, f.beam);
    auto model = exposureModel(job, grid, f.beam, context);
    const double voxelHeight = job.machine.layerThickness / job.simulation.slicesPerLayer;
    const cure::CureLaw& law = *job.cure;
    // The 3D dose grid exists only when a .vdb is asked for; cure and validation take the
    // slices as they come.
    std::unique_ptr<exposure::DoseVolume> volume;
    if (job.simulation.writeVdb)
        volume = std::make_unique<exposure::DoseVolume>(grid, voxelHeight, 0.0,
                                                        float(0.02 * law.criticalDose()));
    validate::SliceValidator validator(f.part, grid, law, voxelHeight);
    const SimulationSpec& sim = job.simulation;
    const bool keepMesh = keepsCuredView(job);
    const std::vector<exposure::Tile> tiles = exposureTiles(*model, tileSide);
    // Tiles are checkpointed unless a dose volume is kept (its state is the volume itself), and
    // then shared over MPI ranks (each tile's share of the pictures merged on rank 0 too).
    const bool checkpointed = tiles.size() > 1 && !volume;
    const bool distributed = checkpointed && context.cluster && context.cluster->ranks() > 1;
    const std::string partialStl = checkpointDirectory(outDir) + "/cured.stl.partial";
    if (checkpointed) createDirectories(checkpointDirectory(outDir));
    std::unique_ptr<validate::StreamingCuredSurface> cured =
        curedSurfaceSink(job, grid, voxelHeight, f.part,
                         !sim.writes("cured.stl") ? ""
                         : checkpointed           ? partialStl
                                                  : outDir + "/cured.stl",
                         checkpointed);
    keepCuredView(job, f.part, voxelHeight, *cured);
    validate::FeatureProbes features(job.features, grid, law, voxelHeight);
    auto sink = [](auto& consumer) {
        return [&consumer](const exposure::ExposureSlice& s) { consumer.add(s); };
    };
    std::vector<exposure::SliceSink> sinks{sink(validator), sink(*cured), sink(features)};
    PictureRecorders recorders(job, f.part, f.layers, grid);  // pictures: for figures, viewer
    recorders.addSinks(sinks);
    std::optional<report::SectionRecorder>& sections = recorders.sections;
    std::optional<report::LayerSectionRecorder>& layerSections = recorders.layerSections;
    if (volume) sinks.push_back(sink(*volume));
    const auto exposureError =  // the laser review's, from the slices
        planners::laserExposureErrorSink(f.layers, job.machine, law, *model, sim.writes("figures"));
    if (exposureError) sinks.push_back(sink(*exposureError));
    const TileConsumers consumers{validator, *cured, features, exposureError.get()};
    const PictureConsumers pictures = recorders.consumers(job, cured.get(), exposureError.get());
    int firstTile = 0;
    std::function<void(int)> tilesDone;  // checkpoints after each tile (each round over MPI)
    if (checkpointed) {
        TileCheckpoint state{
            inputs,
            checkpointFingerprint(inputs, outDir, {{"side_mm", tileSide}, {"count", tiles.size()}}),
            sha256OfFile(outDir + "/plan.json"), result.plan.planner};
        if (checkpoint) {
            checkFingerprint(*checkpoint, outDir, state.fingerprint);
            consumers.restore(checkpoint->consumers, checkpointDirectory(outDir) + "/state.json");
            if (pictures.any())
                pictures.restore(outDir, checkpoint->consumers.value("pictures", nlohmann::json()));
            firstTile = checkpoint->tilesDone;
            logInfo("resuming after tile " + std::to_string(firstTile) + " of " +
                    std::to_string(tiles.size()));
        }
        tilesDone = [&, state](int done) mutable {
            state.tilesDone = done;
            state.consumers = consumers.save();
            if (pictures.any()) state.consumers["pictures"] = pictures.save(outDir, done);
            saveCheckpoint(outDir, state);
            if (options.stopAfterTiles > 0 && done >= options.stopAfterTiles)
                throw InputError("stopped after tile " + std::to_string(done) +
                                 " (RunOptions::stopAfterTiles)");
        };
    } else if (options.resume) {
        logInfo(
            "--resume: this run keeps no checkpoint (one tile, or exposure.vdb among the "
            "outputs); it starts from the first tile");
    }
    sendTileWork(context, distributed, tileSide, planned.plan, sim.writes("cured.stl"), firstTile,
                 tileStlShare(estimate));
    TileDone afterTile;
    if (distributed) {  // the ranks expose the tiles; rank 0 merges them in order
        exposeTilesOnRanks(
            job, f.part, *model, tiles, planned.plan, f.beam, context, sim.writes("cured.stl"),
            firstTile,
            [&](const std::string& partial) {
                mergeTilePartial(partial, tiles, consumers, pictures);
            },
            [&](const std::string& triangles) { cured->appendStl(triangles); }, tilesDone);
        result.mpi["tiles"] = tileSplitJson(tiles.size(), context.cluster->ranks(), firstTile);
        firstTile = int(tiles.size());  // exposeStage: the summary only
    } else if (checkpointed) {
        afterTile = [&](const exposure::Tile& tile) { tilesDone(tile.index + 1); };
    }
    result.exposure = exposeStage(job, *model, tiles, planned.plan, sinks, f.beam, layers, context,
                                  firstTile, afterTile);
    if (model->usesGpu()) result.exposure.backend = deviceName(context);
    {
        const validate::SliceValidationSummary seen = validator.summary();
        result.exposure.maxDose = seen.maxDose;
        result.exposure.storedVoxels = volume ? volume->activeVoxels() : seen.exposedVoxels;
    }
    result.exposure.keptEnergyFraction = model->keptEnergyFraction();
    if (volume) volume->write(outDir + "/exposure.vdb");
    volume.reset();
    timer.finish("expose");

    cureStage(*cured);
    result.curedVolume = cured->volume();
    if (checkpointed && sim.writes("cured.stl")) {  // the in-place STL becomes the output
        std::error_code error;
        std::filesystem::rename(partialStl, outDir + "/cured.stl", error);
        if (error) throw InputError("cannot move the cured surface into place", partialStl);
        output.record("cured.stl");
    }
    removeCheckpoint(outDir);  // it has done its work (or was of a run that keeps none)
    timer.finish("cure");

    result.validation = validateStage(job, f.part, *cured, validator.summary(), features.result(),
                                      sim.writes("reference.vdb") ? outDir + "/reference.vdb" : "");
    timer.finish("validate");
    if (f.beam.planBeam) {
        result.plan.planner["kernel_mismatch"] =
            kernelMismatch(job, f, *model, result.validation, saved.has_value(), context);
        timer.finish("kernel_mismatch");
    }
    // The planner's own work on the exposed plan (the laser exposure error, DLP comparisons).
    const planners::PlanReview review =
        job.planner->review({f.part, f.layers, f.bounds, planned.plan, job.machine, f.beam.beam,
                             law, job.features, result.validation.features, job.simulation.voxel,
                             voxelHeight, *model, result.validation.slices, job.strategy, outDir,
                             sim.writes("figures"), exposureError.get()});
    result.plan.planner.merge_patch(review.report);
    result.sections = review.sections;
    timer.finish("review");

    Progress progress("report: section, deviation, 3D view and layer error figures", 4);
    if (sections) sections->write(outDir);
    progress.advance();
    // The report's pictures and 3D view: the cured surface as the mesher kept it for them;
    // cured.stl was written as it was made.
    const validate::StreamingCuredSurface::View curedView =
        keepMesh ? cured->view() : validate::StreamingCuredSurface::View{};
    const validate::DeviationStatistics& deviations = result.validation.deviationStatistics;
    const report::DeviationScale scale =
        sim.writes("figures") ? report::writeDeviationFigures(outDir, curedView, deviations, f.part)
                              : report::deviationScale(deviations);
    result.deviationLimit = scale.limit;
    result.beyondDeviationLimit = scale.beyond;
    progress.advance();
    if (sim.writes("viewer"))
        result.viewer = report::writeViewer3d(outDir, curedView, f.part, scale.limit,
                                              job.machine.layerThickness);
    progress.advance();
    if (sim.writes("figures"))
        report::writeLayerErrorPlot(outDir + "/xy_error_per_layer", result.validation.slices);
    progress.advance();
    if (layerSections)
        result.sectionView =
            layerSections->write(outDir, f.beam.monteCarlo ? &*f.beam.monteCarlo : nullptr);
    progress.finish();
    timer.finish("report");
    result.inputs = jobInputs(job);
    writeFileAtomic(outDir + "/report.json", report::toJson(result).dump(2));
    result.files = report::filesWrittenSince(outDir, runStart);
    report::writeHtmlReport(outDir, result);
    output.finish();
    return result;
}

}  // namespace vpsim::pipeline
