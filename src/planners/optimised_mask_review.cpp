#include "vpsim/planners/optimised_mask_review.h"

#include <cmath>

#include "vpsim/core/log.h"
#include "vpsim/core/text.h"
#include "vpsim/plan/dlp_masks.h"
#include "vpsim/report/dlp_figures.h"

namespace vpsim::planners {
namespace {

/// The features simulated under the uniform process at `dose` (mJ/mm^2), mm per probe.
std::vector<double> uniformFeatures(const PlanReviewInputs& in, double dose) {
    const geometry::Bounds& b = in.partBounds;
    const geometry::RasterGrid projector = geometry::RasterGrid::covering(
        {b.lo.x, b.lo.y}, {b.hi.x, b.hi.y}, in.machine.pixelPitch, 2);
    plan::ScanPlan flat = plan::emptyPlan(in.layers, in.machine);
    for (size_t k = 0; k < in.layers.layers.size(); ++k)
        if (!in.layers.layers[k].region.empty())
            flat.layers[k].masks.push_back(
                plan::uniformMask(in.layers.layers[k].region, projector, dose));
    validate::FeatureProbes probes(in.features, in.model.grid(), in.cure, in.voxelHeight);
    in.model.run(flat, [&](const exposure::ExposureSlice& s) { probes.add(s); });
    std::vector<double> out;
    for (size_t i = 0; i < in.features.size(); ++i) out.push_back(probes.simulated(i));
    logInfo("uniform comparison simulated at " + formatNumber(dose * 100.0, 4) + " mJ/cm^2");
    return out;
}

std::string cell(const nlohmann::json& object, const char* key) {
    return object.contains(key) && object[key].is_number()
               ? formatNumber(object[key].get<double>(), 4)
               : std::string();
}

report::ReportTable featuresTable(const PlanReviewInputs& in, const std::vector<double>& uniform,
                                  double uniformDose) {
    report::ReportTable t;
    t.header = {"feature (mm)", "objective"};
    if (!uniform.empty())
        t.header.push_back("uniform plan, " + formatNumber(uniformDose * 100.0, 4) +
                           " mJ/cm² (simulated)");
    t.header.insert(t.header.end(), {"this plan (simulated)", "measured mean"});
    const validate::FeatureMeasurements& f = in.featureResults;
    for (size_t i = 0; i < f.probes.size(); ++i) {
        double mean = 0;
        for (double m : f.probes[i].measured) mean += m / double(f.probes[i].measured.size());
        std::vector<std::string> row{f.probes[i].name, formatNumber(f.probes[i].objective, 4)};
        if (!uniform.empty()) row.push_back(formatNumber(uniform[i], 4));
        row.push_back(formatNumber(f.simulated[i], 4));
        row.push_back(f.probes[i].measured.empty() ? "" : formatNumber(mean, 4));
        t.rows.push_back(std::move(row));
    }
    return t;
}

report::ReportTable xyTable(const nlohmann::json& xy) {
    report::ReportTable t;
    t.header = {"xy coupling (from " + xy.value("start", std::string()) + ")", "column optimum",
                "joint optimum"};
    t.rows = {{"XY contour error, this run's validation (mm)",
               cell(xy, "validation_xy_contour_error_columns_mm"),
               cell(xy, "validation_xy_contour_error_xy_mm")},
              {"XY contour error, optimiser's model (mm)", cell(xy, "contour_error_columns_mm"),
               cell(xy, "contour_error_xy_mm")},
              {"shape objective J", cell(xy, "objective_columns"), cell(xy, "objective_xy")}};
    return t;
}

}  // namespace

PlanReview optimisedMaskReview(const PlanReviewInputs& in, const OptimisedMaskArtefacts& a) {
    PlanReview review;
    report::ReportSection section;
    section.title = "Optimised DLP masks";
    const nlohmann::json& summary = a.summary;
    std::vector<double> uniform;
    double uniformDose = 0;
    if (summary.contains("uniform_comparison") && !in.features.empty()) {
        uniformDose = summary["uniform_comparison"].value("dose_mJ_per_cm2", 0.0) / 100.0;
        uniform = uniformFeatures(in, uniformDose);
        nlohmann::json list = nlohmann::json::array();
        for (size_t i = 0; i < in.features.size(); ++i)
            list.push_back({{"name", in.features[i].name}, {"simulated_mm", uniform[i]}});
        review.report["uniform_comparison"]["features"] = std::move(list);
    }
    if (!in.featureResults.probes.empty())
        section.tables.push_back(featuresTable(in, uniform, uniformDose));
    // xy coupling: the column optimum simulated beside the joint one, validated the same way.
    if (!a.columnPlan.layers.empty() && summary.contains("xy_coupling") &&
        summary["xy_coupling"].is_object()) {
        validate::SliceValidator validator(in.part, in.model.grid(), in.cure, in.voxelHeight);
        in.model.run(a.columnPlan, [&](const exposure::ExposureSlice& s) { validator.add(s); });
        nlohmann::json xy = summary["xy_coupling"];
        xy["validation_xy_contour_error_columns_mm"] = validator.summary().xyContourErrorMean;
        xy["validation_xy_contour_error_xy_mm"] = in.validation.xyContourErrorMean;
        review.report["xy_coupling"] = xy;
        section.tables.push_back(xyTable(xy));
    }
    if (!in.figures) {  // simulation.outputs leaves the figures out: the tables only
        review.sections.push_back(std::move(section));
        return review;
    }
    std::vector<double> histogram;
    if (summary.contains("grey_histogram"))
        histogram = summary["grey_histogram"].get<std::vector<double>>();
    std::vector<double> uniformPerProbe = uniform;
    uniformPerProbe.resize(in.featureResults.probes.size(), NAN);
    report::writeDlpFigures(in.outDir,
                            {in.plan, a.figures, in.featureResults, uniformPerProbe, histogram});
    section.figures = {
        {"dlp_features.svg",
         "features: objective, the uniform plan and this plan simulated, measured (mm)"},
        {"dlp_dose_along_z.svg",
         "dose per layer along Z through one pixel column (seed 001 "
         "Fig. 13-16)"},
        {"dlp_conversion_along_z.svg",
         "conversion along Z through the same column, with the gel point and the target"},
        {"dlp_mask.svg",
         "one layer's greyscale mask (grey as projected, mm axes, grey-to-dose scale)"},
        {"dlp_grey_histogram.svg", "histogram of the grey levels of all exposed pixels"}};
    review.sections.push_back(std::move(section));
    return review;
}

}  // namespace vpsim::planners
