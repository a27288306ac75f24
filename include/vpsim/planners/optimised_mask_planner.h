#pragma once
/// @file
/// Planner "optimised-mask" (DLP, seed 001 Section 3 and beyond): every pixel of every layer
/// gets its own dose from the column optimiser (optimise/dlp/pattern_search.h, or geometric.h,
/// or jointly through the blur, xy.h), quantised to the projector's grey levels
/// (optimise/dlp/mask_optimiser.h). The grey-level calibration comes from machine.grey_levels
/// and machine.exposure_time (plan::Machine), or from the same keys in the plan section. Needs a
/// cure law with conversion kinetics (CureLaw::conversionKinetics: K, gel point) and a
/// penetration depth. Its review (optimised_mask_review.h) simulates the uniform process and,
/// with xy coupling, the column optimum beside the plan, and draws the DLP figures.

#include "vpsim/optimise/dlp/mask_optimiser.h"
#include "vpsim/planners/planner.h"

namespace vpsim::planners {

KeyTable optimisedMaskKeyTable();
/// The optimiser's settings from the plan section. @throw InputError naming the key
optimise::DlpMaskPlannerSettings readOptimisedMaskSettings(const KeyReader& keys);

/// Registers "optimised-mask".
void registerOptimisedMaskPlanner(PlannerRegistry& registry);

}  // namespace vpsim::planners
