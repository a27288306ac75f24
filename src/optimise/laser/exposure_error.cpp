#include "vpsim/optimise/laser/exposure_error.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"

#include "exposure_error_sum.h"

#include <tbb/parallel_for.h>

namespace vpsim::optimise {

std::vector<char> insideMask(const geometry::PolygonSet& region, const exposure::SurfaceGrid& g) {
    std::vector<char> mask(size_t(g.nx) * g.ny, 0);
    for (int j = 0; j < g.ny; ++j)
        for (const auto& [x0, x1] : region.intervalsAt(g.centreY(j))) {
            // Cells of the whole grid first (as untiled), then of this window.
            int i0 = std::max(0, int(std::ceil((x0 - g.originX) / g.pitch - 0.5)) - g.firstI);
            int i1 =
                std::min(g.nx - 1, int(std::floor((x1 - g.originX) / g.pitch - 0.5)) - g.firstI);
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

namespace vpsim::optimise {

namespace {

/// The fitted kernel's layer map at depth d is exp(-d/De) times the one at the surface, so the
/// total surface exposure of layer k is R_k = B_k + a R_{k+1} (a = exp(-lt/De)): one blur per
/// layer, from the top down, instead of one per pair of layers; and no deposit is kept.
template <typename PerLayer>
void fittedSurfaceExposures(exposure::ExposureEngine& engine, const plan::ScanPlan& plan,
                            double decay, const PerLayer& perLayer) {
    exposure::SurfaceGrid running = engine.grid().surface(), deposit = engine.grid().surface();
    for (int k = int(plan.layers.size()) - 1; k >= 0; --k) {
        std::fill(deposit.values.begin(), deposit.values.end(), 0.0f);
        exposure::depositLayer(plan.layers[k], deposit);
        const exposure::SurfaceGrid own = engine.layerMap(deposit, 0.0);
        const float a = float(decay);
        tbb::parallel_for(size_t(0), running.values.size(), [&](size_t c) {
            running.values[c] = own.values[c] + a * running.values[c];
        });
        perLayer(k, own, running);
    }
}

}  // namespace

nlohmann::json planExposureError(exposure::ExposureModel& model, const plan::ScanPlan& plan,
                                 const std::vector<geometry::PolygonSet>& regions,
                                 double targetDose, double band, ExposureError* all,
                                 exposure::SurfaceGrid* topOwnMap) {
    if (plan.layers.size() != regions.size())
        throw InputError("exposure error: one region per plan layer is needed");
    if (!(targetDose > 0) || !(band >= 0))
        throw InputError("exposure error: Etar must be positive and the band non-negative");
    const double lt = model.layerThickness();
    int topLayer = -1;
    for (int k = int(regions.size()) - 1; k >= 0 && topLayer < 0; --k)
        if (!regions[k].empty()) topLayer = k;
    std::vector<ExposureError> errors(regions.size());
    detail::ErrorHistogram histogram;
    auto measure = [&](int k, const exposure::SurfaceGrid& own,
                       const exposure::SurfaceGrid& total) {
        if (regions[k].empty()) return;
        errors[k] =
            detail::windowError(total, {0, 0, total.nx, total.ny}, insideMask(regions[k], total),
                                insideMask(regions[k].offset(band), total), targetDose, 1.0,
                                all ? &histogram : nullptr);
        if (k == topLayer && topOwnMap) *topOwnMap = own;
    };
    if (auto* fitted = dynamic_cast<exposure::ExposureEngine*>(&model)) {
        fittedSurfaceExposures(*fitted, plan, std::exp(-lt / fitted->beam().attenuationLength),
                               measure);
    } else {  // any other model: Eq. 21 through layerMap at each depth
        std::vector<exposure::SurfaceGrid> deposits(regions.size(), model.grid().surface());
        for (size_t k = 0; k < regions.size(); ++k)
            exposure::depositLayer(plan.layers[k], deposits[k]);
        for (int k = 0; k < int(regions.size()); ++k) {
            if (regions[k].empty()) continue;
            const exposure::SurfaceGrid own = model.layerMap(deposits[k], 0.0);
            exposure::SurfaceGrid map = own;
            for (int j = k + 1; j < int(regions.size()); ++j) {
                exposure::SurfaceGrid sent = model.layerMap(deposits[j], (j - k) * lt);
                double peak = 0;
                for (size_t c = 0; c < map.values.size(); ++c) {
                    map.values[c] += sent.values[c];
                    peak = std::max(peak, double(sent.values[c]));
                }
                if (peak < 1e-6 * targetDose) break;  // deeper layers send nothing measurable
            }
            measure(k, own, map);
        }
    }
    return detail::exposureErrorJson(errors, regions, targetDose, band, histogram, all);
}

}  // namespace vpsim::optimise
