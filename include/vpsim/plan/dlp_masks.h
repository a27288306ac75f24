#pragma once
/// @file
/// Uniform-dose DLP masks: the non-optimised process of seed 001, one dose for every pixel of the
/// layer's region.

#include "vpsim/geometry/polygons.h"
#include "vpsim/geometry/raster.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::plan {

enum class MaskRasterMode {
    Binary,     ///< full dose where the pixel centre is inside the region (a plain projector)
    Greyscale,  ///< dose scaled by the exact area fraction of the pixel inside (anti-aliased)
};

/// The mask projecting `dose` (mJ/mm^2) over `region` on the projector's pixel grid.
/// @throw InputError for a negative dose
MaskImage uniformMask(const geometry::PolygonSet& region, const geometry::RasterGrid& grid,
                      double dose, MaskRasterMode mode = MaskRasterMode::Binary);

}  // namespace vpsim::plan
