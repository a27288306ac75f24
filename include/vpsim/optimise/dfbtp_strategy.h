#pragma once
/// @file
/// Planners "dfbtp" (seed 000 Section III, optimise/dfbtp_planner.h) and "inverse"
/// (optimise/inverse_planner.h) behind the planner interface, with the shared laser keys
/// (plan/laser_plan_options.h) plus their own (optimise/dfbtp_config.h).

#include "vpsim/plan/planner.h"

namespace vpsim::optimise {

/// Registers "dfbtp" and "inverse".
void registerLaserOptimisers(plan::PlannerRegistry& registry);

}  // namespace vpsim::optimise
