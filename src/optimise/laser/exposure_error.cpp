#include "vpsim/optimise/laser/exposure_error.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/core/image.h"
#include "vpsim/exposure/deposit.h"

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

namespace vpsim::optimise {

void writeErrorCurves(const std::string& path,
                      const std::vector<std::pair<std::string, ExposureError>>& curves) {
    std::vector<PlotSeries> series;
    for (const auto& [label, e] : curves) {
        PlotSeries s;
        s.label = label + " (SSE " + std::to_string(int(std::lround(e.sse))) + " mJ^2/mm^4)";
        const size_t n = e.sortedRelative.size(), step = std::max<size_t>(1, n / 400);
        for (size_t i = 0; i < n; i += step) {
            s.x.push_back(double(i) / std::max<size_t>(1, n - 1));
            s.y.push_back(e.sortedRelative[i]);
        }
        if (n > 0) s.x.push_back(1.0), s.y.push_back(e.sortedRelative.back());
        series.push_back(std::move(s));
    }
    writeSvgLinePlot(path, "Sorted exposure error (seed 000 Fig. 23)", "fraction of cells",
                     "|E - Etm| / Etar", series);
}

void writeExposurePicture(const std::string& path, const exposure::SurfaceGrid& exposure,
                          double targetDose, double contourLevel) {
    std::vector<float> flipped(exposure.values.size());
    for (int j = 0; j < exposure.ny; ++j)  // heatMap rows run from the top
        for (int i = 0; i < exposure.nx; ++i)
            flipped[size_t(exposure.ny - 1 - j) * exposure.nx + i] = exposure.at(i, j);
    writePng(path, heatMap(flipped, exposure.nx, exposure.ny, 0.0, 1.5 * targetDose,
                           {contourLevel, targetDose}));
}

}  // namespace vpsim::optimise

namespace vpsim::optimise {

nlohmann::json planExposureError(exposure::ExposureModel& model, const plan::ScanPlan& plan,
                                 const std::vector<geometry::PolygonSet>& regions,
                                 double targetDose, double band, ExposureError* all) {
    if (plan.layers.size() != regions.size())
        throw InputError("exposure error: one region per plan layer is needed");
    std::vector<exposure::SurfaceGrid> deposits(regions.size(), model.grid().surface());
    for (size_t k = 0; k < regions.size(); ++k) exposure::depositLayer(plan.layers[k], deposits[k]);
    const double lt = model.layerThickness();
    nlohmann::json layers = nlohmann::json::array(), top = nlohmann::json::object();
    ExposureError total;
    int topLayer = -1;
    for (int k = int(regions.size()) - 1; k >= 0; --k)
        if (!regions[k].empty()) {
            topLayer = k;
            break;
        }
    for (int k = 0; k < int(regions.size()); ++k) {
        if (regions[k].empty()) continue;
        exposure::SurfaceGrid map = model.layerMap(deposits[k], 0.0);
        for (int j = k + 1; j < int(regions.size()); ++j) {  // Eq. 21 through the model
            exposure::SurfaceGrid sent = model.layerMap(deposits[j], (j - k) * lt);
            double peak = 0;
            for (size_t c = 0; c < map.values.size(); ++c) {
                map.values[c] += sent.values[c];
                peak = std::max(peak, double(sent.values[c]));
            }
            if (peak < 1e-6 * targetDose) break;  // deeper layers send nothing measurable
        }
        ExposureError e = layerExposureError(map, regions[k], targetDose, band);
        nlohmann::json row{{"layer", k},
                           {"sse_mJ2_per_mm4", e.sse},
                           {"rms_over_Etar", e.rmsRelative},
                           {"max_over_Etar", e.maxRelative}};
        if (k == topLayer) top = row;
        layers.push_back(row);
        total.sse += e.sse;
        total.cells += e.cells;
        total.maxRelative = std::max(total.maxRelative, e.maxRelative);
        if (all)
            total.sortedRelative.insert(total.sortedRelative.end(), e.sortedRelative.begin(),
                                        e.sortedRelative.end());
    }
    if (total.cells > 0) total.rmsRelative = std::sqrt(total.sse / total.cells) / targetDose;
    if (all) {
        std::sort(total.sortedRelative.begin(), total.sortedRelative.end());
        *all = total;
    }
    top.erase("layer");
    return {{"band_um", band * 1e3},
            {"target_dose_mJ_per_cm2", targetDose * 100},
            {"sse_mJ2_per_mm4", total.sse},
            {"rms_over_Etar", total.rmsRelative},
            {"max_over_Etar", total.maxRelative},
            {"top_layer", top},
            {"layers", layers}};
}

}  // namespace vpsim::optimise
