#pragma once
/// @file
/// The laser plan's exposure-error stage of a run (issue 11 item 6), the same for every laser
/// strategy so that `--set plan.strategy=aces|dfbtp|inverse` report side by side.

#include <string>

#include <nlohmann/json.hpp>

#include "vpsim/geometry/layer_stack.h"
#include "vpsim/pipeline/stages.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::pipeline {

/// report.json's `layer_exposure_error` of a laser plan (optimise::planExposureError): on the
/// job's voxel pitch with the fitted beam, against Etar = Ec exp((lt - zmax)/De3D) inside and 0
/// outside, over the part plus Reff. Writes `exposure_error_sorted.svg` (Fig. 23) and
/// `exposure_top_layer.svg` (the top layer's surface exposure) into `outDir`. Returns null for
/// a DLP plan or a plan without layers.
nlohmann::json laserErrorStage(const Job& job, const geometry::LayerStack& layers,
                               const plan::ScanPlan& plan, const BeamResult& beam,
                               const std::string& outDir);

}  // namespace vpsim::pipeline
