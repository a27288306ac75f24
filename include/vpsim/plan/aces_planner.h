#pragma once
/// @file
/// Planner "aces": every layer hatched by ACES (aces.h) with the job's fitted beam.

#include "vpsim/plan/planner.h"

namespace vpsim::plan {

/// Registers "aces".
void registerAcesPlanner(PlannerRegistry& registry);

}  // namespace vpsim::plan
