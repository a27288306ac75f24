#pragma once
/// @file
/// The report figures of a DLP mask plan optimised per pixel (planner `optimised-mask`, seed 001
/// Section 3): the features table of the uniform and the optimised plan side by side (Table 2),
/// dose and conversion along Z through one pixel column (Fig. 13-16), one layer's greyscale mask
/// with mm axes and a grey/dose scale, and the histogram of the grey levels. SVG files in the
/// output directory, with a section of index.html that shows them.

#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "vpsim/plan/scan_plan.h"
#include "vpsim/report/job_result.h"

namespace vpsim::report {

/// Files writeDlpFigures may write (in index.html's order).
inline constexpr const char* DLP_FIGURE_FILES[] = {"dlp_features.svg", "dlp_dose_along_z.svg",
                                                   "dlp_conversion_along_z.svg", "dlp_mask.svg",
                                                   "dlp_grey_histogram.svg"};

/// Writes the figures into `outDir` from the planner's figure data (optimise::
/// dlpReportFigureData), the plan's masks and the run's features; the features figure needs the
/// job's features, the uniform ones come from result.plan.planner["uniform_comparison"].
/// Also writes dlp_figures.json (the data drawn). @throw InputError when a file cannot be written
void writeDlpFigures(const std::string& outDir, const plan::ScanPlan& plan,
                     const nlohmann::json& figureData, const JobResult& result);

/// Appends the DLP section of index.html (features side by side, figures present in outDir);
/// nothing for runs without the planner's figures.
void writeDlpHtmlSection(std::ostringstream& html, const std::string& outDir,
                         const JobResult& result);

}  // namespace vpsim::report
