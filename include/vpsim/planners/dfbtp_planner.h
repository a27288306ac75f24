#pragma once
/// @file
/// Planner "dfbtp" (seed 000 Section III, optimise/laser/dfbtp.h) behind the planner interface,
/// with the shared laser keys (laser_plan_options.h) plus its own.

#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/planners/planner.h"

namespace vpsim::planners {

/// The shared laser keys, the planning grid's and the liftings a_i.
KeyTable dfbtpKeyTable();
/// DFBTP's own parameters (the ACES part is filled from the shared keys at plan()).
/// @throw InputError naming the key
optimise::DfbtpParameters readDfbtpParameters(const KeyReader& keys);

/// Registers "dfbtp".
void registerDfbtpPlanner(PlannerRegistry& registry);

}  // namespace vpsim::planners
