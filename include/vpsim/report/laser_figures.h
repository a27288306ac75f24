#pragma once
/// @file
/// The laser plan's exposure-error pictures of a run (issue 11 item 6): seed 000's Fig. 23 (the
/// sorted |error| / Etar over the cells of every layer) and the seed-style single-layer map (the
/// top layer's surface exposure with the model's outline, Fig. 21/22 as a top view).

#include <string>
#include <utility>
#include <vector>

#include "vpsim/exposure/surface_grid.h"
#include "vpsim/geometry/polygons.h"

namespace vpsim::report {

/// Fig. 23 as an SVG line chart: for each (label, ascending |E - Etm| / Etar), the error against
/// the fraction of cells (at most 400 points per curve). @throw InputError when it cannot be
/// written
void writeSortedErrorFigure(const std::string& path,
                            const std::vector<std::pair<std::string, std::vector<float>>>& curves);

/// The single-layer figure as SVG: the surface exposure (mJ/mm^2 on `map`) as a viridis heat map
/// from 0 to 1.5 Etar, embedded as a PNG, with x and y axes in mm, a colour bar in mJ/cm^2 with
/// Etar and Ec marked, and the model's outline `region` in red.
/// @throw InputError when it cannot be written
void writeLayerExposureFigure(const std::string& path, const exposure::SurfaceGrid& map,
                              const geometry::PolygonSet& region, double targetDose,
                              double criticalDose, const std::string& title);

}  // namespace vpsim::report
