#pragma once
/// @file
/// The deviation figures of a run, through the plotting layer (plot.h): the histogram of the
/// signed surface deviation and the cured surface seen from above, coloured by the deviation of
/// its top surface in µm on a diverging scale centred on 0, with the model's and the cured
/// silhouettes in a legend and the share of the surface beyond the scale stated.

#include <string>
#include <vector>

#include "vpsim/geometry/mesh.h"
#include "vpsim/validate/streaming_surface.h"
#include "vpsim/validate/surface_deviation.h"

namespace vpsim::report {

/// The symmetric deviation scale of a run: a round value near the 95th percentile of
/// |deviation| (mm), and the share of the samples beyond it.
struct DeviationScale {
    double limit = 0;   ///< mm
    double beyond = 0;  ///< fraction of the samples with |deviation| > limit
};
/// From the running statistics of every vertex (the percentile and the share to their bin).
DeviationScale deviationScale(const validate::DeviationStatistics& statistics);

/// Writes deviation_histogram (of every vertex: `statistics`) and deviation_map_top (the cured
/// surface as kept for pictures) as .svg and .png into `directory`; nothing when there are no
/// deviations. Returns the scale used. @throw InputError when a file cannot be written
DeviationScale writeDeviationFigures(const std::string& directory,
                                     const validate::StreamingCuredSurface::View& cured,
                                     const validate::DeviationStatistics& statistics,
                                     const geometry::Mesh& part);

}  // namespace vpsim::report
