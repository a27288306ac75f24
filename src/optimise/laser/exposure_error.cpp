#include "vpsim/optimise/laser/exposure_error.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

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

namespace {

/// |E - Etm| / Etar of every counted cell of every layer, as a histogram: the sorted curve of
/// Fig. 23 over 1e8 cells would otherwise be a 400 MB sort, and its figure shows 400 points.
/// Bins of 1/16384 Etar up to 4 Etar (the curve's error is under a bin), exact values beyond.
class ErrorHistogram {
public:
    static constexpr int BINS = 65536;
    static constexpr float SCALE = 16384.0f;  ///< bins per Etar
    ErrorHistogram() : mCounts(BINS, 0) {}
    void add(float relative, uint64_t* counts, std::vector<float>& beyond) const {
        const float bin = relative * SCALE;
        if (bin < float(BINS))
            ++counts[int(bin)];
        else
            beyond.push_back(relative);
    }
    void merge(const std::vector<uint64_t>& counts, const std::vector<float>& beyond) {
        for (int b = 0; b < BINS; ++b) mCounts[b] += counts[b];
        mBeyond.insert(mBeyond.end(), beyond.begin(), beyond.end());
    }
    /// The sorted curve at 2001 evenly spaced ranks (first and last exact to a bin).
    std::vector<float> quantiles(uint64_t cells) {
        std::vector<float> out;
        if (cells == 0) return out;
        std::sort(mBeyond.begin(), mBeyond.end());
        const int points = 2001;
        uint64_t below = 0;
        int b = 0;
        for (int q = 0; q < points; ++q) {
            const uint64_t rank = uint64_t(double(q) / (points - 1) * double(cells - 1));
            while (b < BINS && below + mCounts[b] <= rank) below += mCounts[b++];
            out.push_back(b < BINS ? (float(b) + 0.5f) / SCALE : mBeyond[rank - below]);
        }
        return out;
    }

private:
    std::vector<uint64_t> mCounts;
    std::vector<float> mBeyond;
};

/// One layer's metric on a total surface exposure, without the per-layer sort: rows in
/// parallel, each row's sums kept apart and added in row order (the result does not depend on
/// the threads).
/// Each thread's histogram counts and values beyond its range, kept over every layer and merged
/// once (integer counts and a list sorted later: the merge order does not matter).
using LocalHistograms =
    tbb::enumerable_thread_specific<std::pair<std::vector<uint64_t>, std::vector<float>>>;

ExposureError layerErrorAccumulated(const exposure::SurfaceGrid& exposure,
                                    const geometry::PolygonSet& region, double targetDose,
                                    double band, ErrorHistogram* histogram,
                                    LocalHistograms& local) {
    const std::vector<char> inside = insideMask(region, exposure);
    const std::vector<char> counted = insideMask(region.offset(band), exposure);
    const int nx = exposure.nx, ny = exposure.ny;
    std::vector<double> rowSse(ny, 0.0);
    std::vector<float> rowMax(ny, 0.0f);
    std::vector<int> rowCells(ny, 0);
    const float inverseTarget = float(1.0 / targetDose);
    tbb::parallel_for(tbb::blocked_range<int>(0, ny, 16), [&](const tbb::blocked_range<int>& r) {
        auto& [counts, beyond] = local.local();
        for (int j = r.begin(); j < r.end(); ++j) {
            double sse = 0;
            float hi = 0;
            int cells = 0;
            for (int i = 0; i < nx; ++i) {
                const size_t c = size_t(j) * nx + i;
                if (!counted[c]) continue;
                const double err = exposure.values[c] - (inside[c] ? targetDose : 0.0);
                sse += err * err;
                const float relative = float(std::abs(err)) * inverseTarget;
                hi = std::max(hi, relative);
                ++cells;
                if (histogram) histogram->add(relative, counts.data(), beyond);
            }
            rowSse[j] = sse;
            rowMax[j] = hi;
            rowCells[j] = cells;
        }
    });
    ExposureError e;
    for (int j = 0; j < ny; ++j) {
        e.sse += rowSse[j];
        e.cells += rowCells[j];
        e.maxRelative = std::max(e.maxRelative, double(rowMax[j]));
    }
    if (e.cells > 0) e.rmsRelative = std::sqrt(e.sse / e.cells) / targetDose;
    return e;
}

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
    for (int k = int(regions.size()) - 1; k >= 0; --k)
        if (!regions[k].empty()) {
            topLayer = k;
            break;
        }
    std::vector<ExposureError> errors(regions.size());
    ErrorHistogram histogram;
    LocalHistograms local([] {
        return std::make_pair(std::vector<uint64_t>(ErrorHistogram::BINS, 0), std::vector<float>());
    });
    auto measure = [&](int k, const exposure::SurfaceGrid& own,
                       const exposure::SurfaceGrid& total) {
        if (regions[k].empty()) return;
        errors[k] = layerErrorAccumulated(total, regions[k], targetDose, band,
                                          all ? &histogram : nullptr, local);
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
    nlohmann::json layers = nlohmann::json::array(), top = nlohmann::json::object();
    ExposureError total;
    for (int k = 0; k < int(regions.size()); ++k) {
        if (regions[k].empty()) continue;
        const ExposureError& e = errors[k];
        nlohmann::json row{{"layer", k},
                           {"sse_mJ2_per_mm4", e.sse},
                           {"rms_over_Etar", e.rmsRelative},
                           {"max_over_Etar", e.maxRelative}};
        if (k == topLayer) top = row;
        layers.push_back(row);
        total.sse += e.sse;
        total.cells += e.cells;
        total.maxRelative = std::max(total.maxRelative, e.maxRelative);
    }
    if (total.cells > 0) total.rmsRelative = std::sqrt(total.sse / total.cells) / targetDose;
    if (all) {
        for (const auto& [counts, beyond] : local) histogram.merge(counts, beyond);
        total.sortedRelative = histogram.quantiles(uint64_t(total.cells));
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
