#pragma once
/// @file
/// Planner "aces": every layer hatched by ACES (aces.h) with the job's fitted beam.

#include "vpsim/planners/planner.h"

namespace vpsim::planners {

/// Registers "aces".
void registerAcesPlanner(PlannerRegistry& registry);

}  // namespace vpsim::planners
