#pragma once
/// @file
/// Planner "uniform-mask" (DLP): one dose for every pixel of each layer's region, seed 001's
/// non-optimised process. Keys: "dose" (default 78 mJ/cm^2), "greyscale" (anti-aliased edge
/// pixels, default false).

#include "vpsim/planners/planner.h"

namespace vpsim::planners {

/// Registers "uniform-mask".
void registerUniformMaskPlanner(PlannerRegistry& registry);

}  // namespace vpsim::planners
