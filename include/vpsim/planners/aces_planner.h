#pragma once
/// @file
/// Planner "aces": every layer hatched by ACES (aces.h) with the job's fitted beam.

#include "vpsim/planners/laser_plan_options.h"
#include "vpsim/planners/planner.h"

namespace vpsim::planners {

/// The shipped ACES plan of every layer, designed top down with the stack-aware contour rule
/// (each layer's edge offset counts what the layers above send to its wall): what `aces` plans
/// and what `inverse` starts from. `summary` (optional) receives its summary().
plan::ScanPlan acesStackPlan(const PlannerInputs& inputs, const LaserPlanOptions& options,
                             nlohmann::json* summary = nullptr);

/// Registers "aces".
void registerAcesPlanner(PlannerRegistry& registry);

}  // namespace vpsim::planners
