#pragma once
/// @file
/// The laser plan's exposure-error review (seed 000 Section III-B, Fig. 23), the default review of
/// every laser planner (Planner::review) so that `--set plan.strategy=aces|dfbtp|inverse` report
/// side by side.

#include "vpsim/planners/planner.h"

namespace vpsim::planners {

/// report.json's `layer_exposure_error` (optimise::planExposureError): on the job's voxel pitch
/// with the fitted beam, against Etar = Ec exp((lt - zmax)/De3D) inside and 0 outside, over the
/// part plus Reff. Writes `exposure_error_sorted.svg` (Fig. 23) and `exposure_top_layer.svg`
/// (the top layer's surface exposure) into the output directory and lists them in a section.
/// Nothing for a plan without laser layers.
PlanReview laserExposureReview(const PlanReviewInputs& inputs);

}  // namespace vpsim::planners
