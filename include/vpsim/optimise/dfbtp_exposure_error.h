#pragma once
/// @file
/// The seed's exposure-error metric (seed 000 Section III-B, Fig. 23): on a layer's total surface
/// exposure (its own map plus what the layers above transmit), the error against the target map
/// (Etar inside the region, 0 outside) over the region grown by a band (Reff), summed over grid
/// cells: the squared error sum in mJ^2/mm^4 (so it depends on the grid: the seed's figures are
/// on a 10 um grid), its RMS as a fraction of Etar, and the sorted |error| / Etar curve.

#include <vector>

#include "vpsim/exposure/surface_grid.h"
#include "vpsim/geometry/polygons.h"

namespace vpsim::optimise {

struct ExposureError {
    double sse = 0;                     ///< sum over cells of (E - Etm)^2 (mJ^2/mm^4)
    double rmsRelative = 0;             ///< sqrt(sse / cells) / Etar
    double maxRelative = 0;             ///< largest |E - Etm| / Etar
    int cells = 0;                      ///< cells evaluated
    std::vector<float> sortedRelative;  ///< |E - Etm| / Etar, ascending (Fig. 23)
};

/// Cells whose centre lies in `region`, row-major on `grid`'s cells (1 inside).
std::vector<char> insideMask(const geometry::PolygonSet& region, const exposure::SurfaceGrid& grid);

/// The metric above. @throw InputError for a non-positive Etar or a negative band
ExposureError layerExposureError(const exposure::SurfaceGrid& exposure,
                                 const geometry::PolygonSet& region, double targetDose,
                                 double band);

}  // namespace vpsim::optimise
