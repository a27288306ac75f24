#pragma once
/// @file
/// The report stage of a DLP plan optimised per pixel (planner `optimised-mask`): the planner
/// leaves its figure data in its summary ("figures") and may ask for a uniform comparison
/// ("uniform_comparison": {"dose_mJ_per_cm2"}). This stage takes the figure data out of the
/// summary (report.json stays lean; the data goes to dlp_figures.json), exposes the uniform plan
/// (every layer's region at that one dose, binary masks on the same projector grid) through the
/// job's exposure model to probe the job's features, stores them in the summary as
/// "uniform_comparison": {"dose_mJ_per_cm2", "features": [{"name", "simulated_mm"}]}, and draws
/// the figures (report/dlp_figures.h). With xy_coupling it also exposes the column optimum's plan
/// (optimisedMaskColumnPlan) and validates it like the run, storing both XY contour errors in
/// "xy_coupling": {"validation_xy_contour_error_columns_mm", "validation_xy_contour_error_xy_mm"}.
/// A no-op for other plans.

#include <string>

#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/layer_stack.h"
#include "vpsim/geometry/mesh.h"
#include "vpsim/pipeline/job.h"
#include "vpsim/report/job_result.h"

namespace vpsim::pipeline {

/// @throw InputError when the figures cannot be written
void dlpReportStage(const Job& job, const geometry::Mesh& part, const geometry::LayerStack& layers,
                    const geometry::Bounds& partBounds, const plan::ScanPlan& plan,
                    exposure::ExposureModel& model, report::JobResult& result,
                    const std::string& outDir);

}  // namespace vpsim::pipeline
