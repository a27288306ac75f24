#pragma once
/// @file
/// The review of an `optimised-mask` plan after the run's exposure: the uniform process of seed
/// 001 (every layer's region at one dose, binary masks on the same projector grid) exposed
/// through the run's model to probe the job's features; with xy coupling the column optimum's
/// plan exposed and validated like the run, to compare XY contour errors; the DLP figures
/// (report/dlp_figures.h) and their section of index.html.

#include "vpsim/planners/planner.h"

namespace vpsim::planners {

/// What an optimised-mask planner keeps of its last plan() for its review.
struct OptimisedMaskArtefacts {
    bool planned = false;
    /// The planner's report.json figures (columns, gaps, grey histogram, "uniform_comparison":
    /// {"dose_mJ_per_cm2"} when a comparison is asked, "xy_coupling": {...}).
    nlohmann::json summary = nlohmann::json::object();
    nlohmann::json figures;  ///< optimise::dlpReportFigureData, drawn and kept out of report.json
    plan::ScanPlan columnPlan;  ///< with xy coupling: the column optimum, else no layers
};

/// Adds "uniform_comparison": {"features": [{"name", "simulated_mm"}]} and "xy_coupling":
/// {"validation_xy_contour_error_columns_mm", "validation_xy_contour_error_xy_mm"} to the report,
/// writes the figures and returns the section listing them.
/// @throw InputError when a figure cannot be written
PlanReview optimisedMaskReview(const PlanReviewInputs& inputs,
                               const OptimisedMaskArtefacts& artefacts);

}  // namespace vpsim::planners
