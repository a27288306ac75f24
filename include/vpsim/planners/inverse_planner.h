#pragma once
/// @file
/// Planner "inverse" (optimise/laser/inverse.h: the whole layer's dot energies by bounded least
/// squares) behind the planner interface, with the shared laser keys (laser_plan_options.h; its
/// ACES warm start defaults to the cure-at-contour edge) plus its own.

#include "vpsim/optimise/laser/inverse.h"
#include "vpsim/planners/planner.h"

namespace vpsim::planners {

/// The shared laser keys (edge defaulting to cure-at-contour), the planning grid's and the
/// iterations.
KeyTable inverseKeyTable();
/// The inverse planner's own parameters (the ACES warm start is filled at plan()).
/// @throw InputError naming the key
optimise::InverseParameters readInverseParameters(const KeyReader& keys);

/// Registers "inverse".
void registerInversePlanner(PlannerRegistry& registry);

}  // namespace vpsim::planners
