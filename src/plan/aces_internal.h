#pragma once
/// @file
/// Pieces of the ACES planner shared between its source files (not public API).

#include "vpsim/plan/aces.h"

namespace vpsim::plan::detail {

/// Adds a centred line (or a spot) for every small feature of `region` to `layer`.
void planSmallFeatures(const geometry::PolygonSet& region, const AcesDesign& design,
                       double laserPower, LayerPlan& layer, AcesLayerInfo& info);

}  // namespace vpsim::plan::detail
