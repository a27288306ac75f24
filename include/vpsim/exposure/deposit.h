#pragma once
/// @file
/// Turns one layer's plan into the energy it delivers per unit area of the resin surface, before
/// the beam profile spreads it: laser vectors deposit power/speed (mJ/mm) along their path, laser
/// points their energy at one spot, masks their dose over their pixels. Blurring this deposit with
/// the beam's normalised profile gives the layer's exposure map (seed 000 Eq. C.6 for a line).

#include "vpsim/exposure/surface_grid.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::exposure {

/// Adds the deposit of `layer` to `grid` (mJ/mm^2). Energy outside the grid is dropped; the
/// caller sizes the grid with a margin of a few beam radii around the part.
/// Points: bilinear splat between the four nearest cell centres (exact energy and centre of
/// energy); vectors: samples at most a quarter cell apart, each splatted the same way; masks:
/// exact area overlap of mask pixels with cells.
void depositLayer(const plan::LayerPlan& layer, SurfaceGrid& grid);

}  // namespace vpsim::exposure
