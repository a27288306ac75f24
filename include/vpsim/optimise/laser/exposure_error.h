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

#include <nlohmann/json.hpp>

#include "vpsim/exposure/exposure_model.h"
#include "vpsim/exposure/surface_grid.h"
#include "vpsim/geometry/polygons.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::optimise {

struct ExposureError {
    double sse = 0;                     ///< sum over cells of (E - Etm)^2 (mJ^2/mm^4)
    double rmsRelative = 0;             ///< sqrt(sse / cells) / Etar
    double maxRelative = 0;             ///< largest |E - Etm| / Etar
    int cells = 0;                      ///< cells evaluated
    std::vector<float> sortedRelative;  ///< |E - Etm| / Etar, ascending (Fig. 23)
};

/// Cells whose centre lies in `region`, row-major on `grid`'s cells (1 inside); a window of a
/// larger grid (firstI, firstJ) gets the larger grid's cells, bit for bit.
std::vector<char> insideMask(const geometry::PolygonSet& region, const exposure::SurfaceGrid& grid);

/// The metric above. @throw InputError for a non-positive Etar or a negative band
ExposureError layerExposureError(const exposure::SurfaceGrid& exposure,
                                 const geometry::PolygonSet& region, double targetDose,
                                 double band);

}  // namespace vpsim::optimise

namespace vpsim::optimise {

/// Issue 11 item 6, `layer_exposure_error` of report.json: for every layer of `plan` (regions
/// bottom first, same count), the metric above on the layer's total surface exposure (its own
/// map plus what the layers above transmit, through `model`), then the total over layers and
/// the seed-style single-layer figure (the top layer, which nothing above reaches):
/// {"band_um", "target_dose_mJ_per_cm2", "sse_mJ2_per_mm4" (total), "rms_over_Etar" (all cells),
///  "top_layer": {"sse_mJ2_per_mm4", "rms_over_Etar", "max_over_Etar"},
///  "layers": [{"layer", "sse_mJ2_per_mm4", "rms_over_Etar", "max_over_Etar"}]}.
/// `all` (optional) receives the metric over all cells of all layers, with the sorted |error|/Etar
/// of all cells of all layers (Fig. 23) at 2001 evenly spaced ranks (from a histogram of bins of
/// Etar/16384, exact beyond 4 Etar). `topOwnMap` (optional) receives the top layer's own map
/// (no print-through). With the fitted engine each layer is blurred once (the print-through
/// recursion R_k = B_k + a R_{k+1}); other models sum Eq. 21 through layerMap at each depth.
/// @throw InputError when the counts differ or Etar <= 0
nlohmann::json planExposureError(exposure::ExposureModel& model, const plan::ScanPlan& plan,
                                 const std::vector<geometry::PolygonSet>& regions,
                                 double targetDose, double band, ExposureError* all = nullptr,
                                 exposure::SurfaceGrid* topOwnMap = nullptr);

}  // namespace vpsim::optimise
