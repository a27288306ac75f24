#pragma once
/// @file
/// The figures of the laser exposure-error metric (exposure_error.h), through the plotting layer
/// (each as `stem`.svg and .png): seed 000's Fig. 23 (the sorted |error| / Etar against the
/// fraction of cells) and the seed-style single-layer map (Fig. 21/22 as a top view). The laser
/// planners' review (planners/laser_exposure_review.h) and bench_laser_planners draw them.

#include <string>
#include <utility>
#include <vector>

#include "vpsim/exposure/surface_grid.h"
#include "vpsim/geometry/polygons.h"

namespace vpsim::optimise {

/// Fig. 23: for each (label, ascending |E - Etm| / Etar), the error against the fraction of cells
/// (at most 400 points per curve). @throw InputError when a file cannot be written
void writeSortedErrorFigure(const std::string& stem, const std::string& title,
                            const std::vector<std::pair<std::string, std::vector<float>>>& curves);

/// The surface exposure (mJ/mm^2 on `map`) as a map in mJ/cm^2 from 0 to 1.5 Etar with mm axes,
/// the iso-exposure lines at Etar and at `criticalDose` (Ec: the cured edge), and the model's
/// outline `region` when given. With `smoothing` (mm, at least the hatch spacing) the Etar line
/// becomes the line at 0.9 Etar of the map averaged over squares of that side: inside a hatched
/// region the exposure ripples about Etar at the hatch spacing, and a line at Etar through every
/// ripple of a whole part is megabytes of SVG that says nothing; the averaged line shows where
/// the exposure falls short (the part's edges). @throw InputError when a file cannot be written
void writeExposureMapFigure(const std::string& stem, const std::string& title,
                            const exposure::SurfaceGrid& map, const geometry::PolygonSet* region,
                            double targetDose, double criticalDose, double smoothing = 0);

}  // namespace vpsim::optimise
