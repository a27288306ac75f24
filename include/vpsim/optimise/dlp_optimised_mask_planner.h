#pragma once
/// @file
/// Planner "optimised-mask" (DLP, seed 001 Section 3 and beyond): every pixel of every layer
/// gets its own dose from the column optimiser (dlp_pattern_search.h, or dlp_geometric.h, or
/// jointly through the blur, dlp_xy.h), quantised to the projector's grey levels. Keys: those of
/// dlp_mask_planner.h. The grey-level calibration comes from machine.grey_levels and
/// machine.exposure_time (plan::Machine), or from the same keys in the plan section.
/// Needs the FPP cure law (K, gel point) and a penetration depth.

#include "vpsim/plan/planner.h"

namespace vpsim::optimise {

/// The column optimum's plan of the last plan() of an "optimised-mask" planner run with
/// xy_coupling (what the joint optimisation started from, quantised), or nullptr for other
/// planners or without xy_coupling: the report simulates it to compare XY contour errors.
const plan::ScanPlan* optimisedMaskColumnPlan(const plan::Planner& planner);

/// Registers "optimised-mask".
void registerOptimisedMaskPlanner(plan::PlannerRegistry& registry);

}  // namespace vpsim::optimise
