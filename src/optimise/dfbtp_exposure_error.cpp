#include "vpsim/optimise/dfbtp_exposure_error.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"

namespace vpsim::optimise {

std::vector<char> insideMask(const geometry::PolygonSet& region, const exposure::SurfaceGrid& g) {
    std::vector<char> mask(size_t(g.nx) * g.ny, 0);
    for (int j = 0; j < g.ny; ++j)
        for (const auto& [x0, x1] : region.intervalsAt(g.centreY(j))) {
            int i0 = std::max(0, int(std::ceil((x0 - g.originX) / g.pitch - 0.5)));
            int i1 = std::min(g.nx - 1, int(std::floor((x1 - g.originX) / g.pitch - 0.5)));
            for (int i = i0; i <= i1; ++i) mask[size_t(j) * g.nx + i] = 1;
        }
    return mask;
}

ExposureError layerExposureError(const exposure::SurfaceGrid& exposure,
                                 const geometry::PolygonSet& region, double targetDose,
                                 double band) {
    if (!(targetDose > 0) || !(band >= 0))
        throw InputError("exposure error: Etar must be positive and the band non-negative");
    const std::vector<char> inside = insideMask(region, exposure);
    const std::vector<char> counted = insideMask(region.offset(band), exposure);
    ExposureError e;
    for (size_t c = 0; c < counted.size(); ++c) {
        if (!counted[c]) continue;
        double err = exposure.values[c] - (inside[c] ? targetDose : 0.0);
        e.sse += err * err;
        e.sortedRelative.push_back(float(std::abs(err) / targetDose));
        ++e.cells;
    }
    std::sort(e.sortedRelative.begin(), e.sortedRelative.end());
    if (e.cells > 0) {
        e.rmsRelative = std::sqrt(e.sse / e.cells) / targetDose;
        e.maxRelative = e.sortedRelative.back();
    }
    return e;
}

}  // namespace vpsim::optimise
