#include "vpsim/pipeline/dlp_report_stage.h"

#include "vpsim/core/log.h"
#include "vpsim/optimise/dlp_optimised_mask_planner.h"
#include "vpsim/plan/dlp_masks.h"
#include "vpsim/plan/planner.h"
#include "vpsim/report/dlp_figures.h"
#include "vpsim/validate/feature_probe.h"
#include "vpsim/validate/slice_validator.h"

namespace vpsim::pipeline {

void dlpReportStage(const Job& job, const geometry::Mesh& part, const geometry::LayerStack& layers,
                    const geometry::Bounds& b, const plan::ScanPlan& plan,
                    exposure::ExposureModel& model, report::JobResult& result,
                    const std::string& outDir) {
    nlohmann::json& summary = result.plan.planner;
    if (!summary.contains("figures")) return;
    const nlohmann::json figures = summary["figures"];
    summary.erase("figures");
    if (summary.contains("uniform_comparison") && !job.features.empty()) {
        nlohmann::json& uniform = summary["uniform_comparison"];
        const double dose = uniform.value("dose_mJ_per_cm2", 0.0) / 100.0;
        // The uniform process of seed 001: the same projector grid as the planners' masks.
        const geometry::RasterGrid projector = geometry::RasterGrid::covering(
            {b.lo.x, b.lo.y}, {b.hi.x, b.hi.y}, job.machine.pixelPitch, 2);
        plan::ScanPlan flat = plan::emptyPlan(layers, job.machine);
        for (size_t k = 0; k < layers.layers.size(); ++k)
            if (!layers.layers[k].region.empty())
                flat.layers[k].masks.push_back(
                    plan::uniformMask(layers.layers[k].region, projector, dose));
        const double voxelHeight = job.machine.layerThickness / job.simulation.slicesPerLayer;
        validate::FeatureProbes probes(job.features, model.grid(), *job.cure, voxelHeight);
        model.run(flat, [&](const exposure::ExposureSlice& s) { probes.add(s); });
        nlohmann::json list = nlohmann::json::array();
        for (size_t i = 0; i < job.features.size(); ++i)
            list.push_back({{"name", job.features[i].name}, {"simulated_mm", probes.simulated(i)}});
        uniform["features"] = std::move(list);
        logInfo("uniform comparison simulated at " + std::to_string(dose * 100.0) + " mJ/cm^2");
    }
    // xy coupling: the column optimum simulated beside the joint one, validated the same way.
    const plan::ScanPlan* columns = optimise::optimisedMaskColumnPlan(*job.planner);
    if (columns && summary.contains("xy_coupling") && summary["xy_coupling"].is_object()) {
        const double voxelHeight = job.machine.layerThickness / job.simulation.slicesPerLayer;
        validate::SliceValidator validator(part, model.grid(), *job.cure, voxelHeight);
        model.run(*columns, [&](const exposure::ExposureSlice& s) { validator.add(s); });
        nlohmann::json& xy = summary["xy_coupling"];
        xy["validation_xy_contour_error_columns_mm"] = validator.summary().xyContourErrorMean;
        xy["validation_xy_contour_error_xy_mm"] = result.validation.slices.xyContourErrorMean;
    }
    report::writeDlpFigures(outDir, plan, figures, result);
}

}  // namespace vpsim::pipeline
