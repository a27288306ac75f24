#pragma once
/// @file
/// The report figures of a DLP mask plan optimised per pixel (planner `optimised-mask`, seed 001
/// Section 3): the features table of the uniform and the optimised plan side by side (Table 2),
/// dose and conversion along Z through one pixel column (Fig. 13-16), one layer's greyscale mask
/// with mm axes and a grey/dose scale, and the histogram of the grey levels. SVG files in the
/// output directory; the planner's review lists them in its section of index.html.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/plan/scan_plan.h"
#include "vpsim/validate/feature_probe.h"

namespace vpsim::report {

/// Files writeDlpFigures may write (in index.html's order).
inline constexpr const char* DLP_FIGURE_FILES[] = {"dlp_features.svg", "dlp_dose_along_z.svg",
                                                   "dlp_conversion_along_z.svg", "dlp_mask.svg",
                                                   "dlp_grey_histogram.svg"};

/// What the figures are drawn from.
struct DlpFigureInputs {
    const plan::ScanPlan& plan;                     ///< the optimised masks
    const nlohmann::json& data;                     ///< the planner's figure data
    const validate::FeatureMeasurements& features;  ///< the run's features (objective, simulated)
    std::vector<double> uniformFeatures;            ///< mm per probe, the uniform plan; NaN: none
    std::vector<double> greyHistogram;              ///< pixel-layers per grey level
};

/// Writes the figures into `outDir` (optimise::dlpReportFigureData's data, the plan's masks and
/// the run's features) and dlp_figures.json (the data drawn); the features figure only when the
/// job has features. @throw InputError when a file cannot be written
void writeDlpFigures(const std::string& outDir, const DlpFigureInputs& inputs);

}  // namespace vpsim::report
