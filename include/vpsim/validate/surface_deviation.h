#pragma once
/// @file
/// Signed distance of the cured surface from the reference model, sampled at the cured mesh's
/// vertices in the reference level set: positive where the cured part sticks out of the model
/// (over-cure), negative where it falls short.

#include <nlohmann/json_fwd.hpp>

#include "vpsim/geometry/level_set.h"
#include "vpsim/geometry/mesh.h"

namespace vpsim::validate {

struct SurfaceDeviation {
    double mean = 0;  ///< signed mean (mm)
    double rms = 0;   ///< root mean square (mm)
    double p95 = 0;   ///< 95th percentile of |deviation| (mm)
    double max = 0;   ///< largest |deviation| (mm)
    size_t samples = 0;
    /// Samples beyond the level set's band, where the distance is only known to exceed it.
    size_t beyondBand = 0;
    nlohmann::json toJson() const;
};

/// @throw InputError when the cured mesh is empty (nothing cured)
SurfaceDeviation measureSurfaceDeviation(const geometry::Mesh& cured,
                                         const geometry::LevelSet& reference);

/// Statistics of signed deviations (mm) sampled in a level set of band half-width `bandHalfWidth`.
/// @throw InputError when there are none (nothing cured)
SurfaceDeviation summarizeDeviations(const std::vector<float>& deviations, double bandHalfWidth);

/// Signed deviations (mm) at each cured vertex, for histograms and deviation maps.
std::vector<float> vertexDeviations(const geometry::Mesh& cured,
                                    const geometry::LevelSet& reference);

}  // namespace vpsim::validate
