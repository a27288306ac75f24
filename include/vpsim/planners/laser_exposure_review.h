#pragma once
/// @file
/// The laser plan's exposure-error review (seed 000 Section III-B, Fig. 23), the default review of
/// every laser planner (Planner::review) so that `--set plan.strategy=aces|dfbtp|inverse` report
/// side by side.

#include <memory>

#include "vpsim/optimise/laser/exposure_error_sink.h"
#include "vpsim/planners/planner.h"

namespace vpsim::planners {

/// report.json's `layer_exposure_error` (optimise::planExposureError): on the job's voxel pitch
/// with the fitted beam, against Etar = Ec exp((lt - zmax)/De3D) inside and 0 outside, over the
/// part plus Reff, on the run's grid (`inputs.model.grid()`): taken from the run's slices when
/// `inputs.exposureError` holds them (the fitted engine), else by exposing the plan again with
/// the fitted beam (the tabulated engine; callers without a sink). Writes
/// `exposure_error_sorted.svg` (Fig. 23) and `exposure_top_layer.svg` (the top layer's surface
/// exposure) into the output directory and lists them in a section. Nothing for a plan without
/// laser layers.
PlanReview laserExposureReview(const PlanReviewInputs& inputs);

/// The slice consumer that gives laserExposureReview its figures from the run's exposure
/// (optimise::ExposureErrorSink, at the surface through the fitted kernel's exp(dz/(2 De))):
/// the same Etar and band as the review, `model`'s grid. nullptr when the machine is not a
/// laser, no layer has a region, or `model` is not the fitted engine (the tabulated kernel's
/// slice 0 is not the fitted surface exposure: the review then computes it on its own).
/// @param figures keep the top layer's map for the review's figure
std::unique_ptr<optimise::ExposureErrorSink> laserExposureErrorSink(
    const geometry::LayerStack& layers, const plan::Machine& machine, const cure::CureLaw& cure,
    const exposure::ExposureModel& model, bool figures);

}  // namespace vpsim::planners
