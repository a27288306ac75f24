#pragma once
/// @file
/// Planner "optimised-mask" (DLP, seed 001 Section 3 and beyond): every pixel of every layer
/// gets its own dose from the column optimiser (dlp_pattern_search.h, or dlp_geometric.h, or
/// jointly through the blur, dlp_xy.h), quantised to the projector's grey levels. Keys: those of
/// dlp_mask_planner.h plus the grey-level calibration, `grey_levels` ([[grey, irradiance], ...])
/// and `exposure_time`, read from the plan section (until the machine section carries them).
/// Needs the FPP cure law (K, gel point) and a penetration depth.

#include "vpsim/plan/planner.h"

namespace vpsim::optimise {

/// Registers "optimised-mask".
void registerOptimisedMaskPlanner(plan::PlannerRegistry& registry);

}  // namespace vpsim::optimise
