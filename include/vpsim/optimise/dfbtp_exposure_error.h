#pragma once
/// @file
/// The seed's exposure-error metric (seed 000 Section III-B, Fig. 23): on a layer's total surface
/// exposure (its own map plus what the layers above transmit), the error against the target map
/// (Etar inside the region, 0 outside) over the region grown by a band (Reff), summed over grid
/// cells: the squared error sum in mJ^2/mm^4 (so it depends on the grid: the seed's figures are
/// on a 10 um grid), its RMS as a fraction of Etar, and the sorted |error| / Etar curve.

#include <string>
#include <utility>
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

namespace vpsim::optimise {

/// Seed 000 Fig. 23: the sorted |error| / Etar of each plan against the fraction of cells, as an
/// SVG line chart (at most 400 points per curve). @throw InputError when it cannot be written
void writeErrorCurves(const std::string& path,
                      const std::vector<std::pair<std::string, ExposureError>>& curves);

/// The seed-style single-layer figure (Fig. 21/22 as a top view): the surface exposure as a heat
/// map from 0 to 1.5 Etar, with iso-lines at Etar and at `contourLevel` (e.g. Ec), as PNG.
/// @throw InputError when it cannot be written
void writeExposurePicture(const std::string& path, const exposure::SurfaceGrid& exposure,
                          double targetDose, double contourLevel);

}  // namespace vpsim::optimise
