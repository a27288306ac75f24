#pragma once
/// @file
/// The plan-size terms of a job's estimate that planners share (orders of magnitude, measured on
/// the built-in planners; tests/pipeline/test_estimate.cpp and the planners' contract test hold
/// them against measured runs). A planner's estimateSize() starts from its process's term and
/// adds its own working set from its own settings.
///  laser   hatch lines at 0.8 w0 (ACES's spacing for 1% homogeneity) across the part's larger
///          side, 1.5 segments each, plus `borderLoops` loops of each layer's contour vertices:
///          LaserVector 48 B, and the trajectories the scan stage adds (a mark and a jump per
///          vector, ScanMove 72 B). Writing plan.json and ordering: measured 2.1 kB per vector
///          at the plan stage's peak (1 m default job).
///  masks   one float mask per layer over the part's box + 2 pixels (plan/dlp_masks.cpp).

#include "vpsim/optimise/laser/inverse_shape.h"
#include "vpsim/planners/planner.h"

namespace vpsim::planners {

PlanSize laserPlanSize(const PlanSizeInputs& inputs, double borderLoops = 1);
PlanSize maskPlanSize(const PlanSizeInputs& inputs);

/// The planning grid of the laser optimisers (dfbtp, inverse): `gridPitch` over the part's box
/// grown by the effective radius + 2 W, a dozen float maps per layer plus the transmitted
/// exposure of every layer, and dots at `dotPitch` (32 B each; kept in the plan when
/// `dotsInPlan`), `iterations` passes over the grid.
PlanSize laserOptimiserPlanSize(const PlanSizeInputs& inputs, double gridPitch, double dotPitch,
                                double iterations, bool dotsInPlan);

/// The inverse planner's shape objective: laserOptimiserPlanSize() plus the 3D fields of the
/// planning grid (`parameters.slicesPerLayer` slices per layer): four exposure fields and the
/// per-voxel targets (9 B), forward and adjoint passes per iteration (coarse ones ~1/6).
PlanSize shapePlanSize(const PlanSizeInputs& inputs, double gridPitch, double dotPitch,
                       const optimise::ShapeParameters& parameters);

}  // namespace vpsim::planners
