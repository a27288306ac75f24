#pragma once
/// @file
/// Pieces of the ACES planner shared between its source files (not public API).

#include "vpsim/plan/aces/aces.h"

namespace vpsim::plan::detail {

/// Exposure of a half field of lines (the last at 0, the others at -l rh) at y beyond the last
/// line, relative to the infinite field's mean (y and rh in units of W).
double halfFieldProfile(double y, double hatchRatio);

/// Adds a centred line (or a spot) for every small feature of `region` to `layer`.
void planSmallFeatures(const geometry::PolygonSet& region, const AcesDesign& design,
                       double laserPower, LayerPlan& layer, AcesLayerInfo& info);

}  // namespace vpsim::plan::detail
