#include "exposure_error_sum.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace vpsim::optimise::detail {

ErrorHistogram::ErrorHistogram()
    : mTotal(std::vector<uint64_t>(BINS, 0), std::vector<float>()),
      mLocal([] { return Counts(std::vector<uint64_t>(BINS, 0), std::vector<float>()); }) {}

void ErrorHistogram::gather() {
    for (Counts& c : mLocal) {
        for (int b = 0; b < BINS; ++b) mTotal.first[b] += c.first[b];
        mTotal.second.insert(mTotal.second.end(), c.second.begin(), c.second.end());
        std::fill(c.first.begin(), c.first.end(), 0);
        c.second.clear();
    }
}

std::vector<float> ErrorHistogram::quantiles(uint64_t cells) {
    std::vector<float> out;
    if (cells == 0) return out;
    gather();
    std::vector<float>& beyond = mTotal.second;
    std::sort(beyond.begin(), beyond.end());
    const int points = 2001;
    uint64_t below = 0;
    int b = 0;
    for (int q = 0; q < points; ++q) {
        const uint64_t rank = uint64_t(double(q) / (points - 1) * double(cells - 1));
        while (b < BINS && below + mTotal.first[b] <= rank) below += mTotal.first[b++];
        out.push_back(b < BINS ? (float(b) + 0.5f) / SCALE : beyond[rank - below]);
    }
    return out;
}

nlohmann::json ErrorHistogram::state() {
    gather();
    nlohmann::json bins = nlohmann::json::array();
    for (int b = 0; b < BINS; ++b)
        if (mTotal.first[b] > 0) bins.push_back({b, mTotal.first[b]});
    return {{"bins", bins}, {"beyond", mTotal.second}};
}

void ErrorHistogram::addState(const nlohmann::json& state) {
    gather();
    for (const auto& pair : state.at("bins")) {
        const int b = pair.at(0).get<int>();
        if (b < 0 || b >= BINS) throw InputError("exposure-error histogram: bin out of range");
        mTotal.first[b] += pair.at(1).get<uint64_t>();
    }
    for (const auto& v : state.at("beyond")) mTotal.second.push_back(v.get<float>());
}

void ErrorHistogram::clear() {
    gather();
    std::fill(mTotal.first.begin(), mTotal.first.end(), 0);
    mTotal.second.clear();
}

ExposureError windowError(const exposure::SurfaceGrid& values, const exposure::CellWindow& window,
                          const std::vector<char>& inside, const std::vector<char>& counted,
                          double targetDose, double scale, ErrorHistogram* histogram) {
    const int nx = window.width(), ny = window.height();
    std::vector<double> rowSse(ny, 0.0);
    std::vector<float> rowMax(ny, 0.0f);
    std::vector<int> rowCells(ny, 0);
    const float inverseTarget = float(1.0 / targetDose);
    tbb::parallel_for(tbb::blocked_range<int>(0, ny, 16), [&](const tbb::blocked_range<int>& r) {
        ErrorHistogram::Counts* counts = histogram ? &histogram->local() : nullptr;
        for (int j = r.begin(); j < r.end(); ++j) {
            const float* row = &values.values[size_t(j + window.j0 - values.firstJ) * values.nx +
                                              size_t(window.i0 - values.firstI)];
            const char* rowInside = &inside[size_t(j) * nx];
            const char* rowCounted = &counted[size_t(j) * nx];
            float hi = 0;
            int cells = 0;
            auto add = [&](int i, double& sse) {
                if (!rowCounted[i]) return;
                const double err = double(row[i]) * scale - (rowInside[i] ? targetDose : 0.0);
                sse += err * err;
                const float relative = float(std::abs(err)) * inverseTarget;
                hi = std::max(hi, relative);
                ++cells;
                if (counts) ErrorHistogram::add(relative, *counts);
            };
            // Four partial sums (cells i mod 4, the tail in the first), added in a fixed order:
            // four chains of additions instead of one, the same sums whatever the threads.
            double sse[4] = {0, 0, 0, 0};
            int i = 0;
            for (; i + 4 <= nx; i += 4) {
                add(i, sse[0]);
                add(i + 1, sse[1]);
                add(i + 2, sse[2]);
                add(i + 3, sse[3]);
            }
            for (; i < nx; ++i) add(i, sse[0]);
            rowSse[j] = (sse[0] + sse[1]) + (sse[2] + sse[3]);
            rowMax[j] = hi;
            rowCells[j] = cells;
        }
    });
    ExposureError e;
    for (int j = 0; j < ny; ++j) addSums(e, {rowSse[j], 0.0, double(rowMax[j]), rowCells[j], {}});
    return e;
}

void addSums(ExposureError& total, const ExposureError& part) {
    total.sse += part.sse;
    total.cells += part.cells;
    total.maxRelative = std::max(total.maxRelative, part.maxRelative);
}

nlohmann::json exposureErrorJson(std::vector<ExposureError>& errors,
                                 const std::vector<geometry::PolygonSet>& regions,
                                 double targetDose, double band, ErrorHistogram& histogram,
                                 ExposureError* all) {
    int topLayer = -1;
    for (int k = int(regions.size()) - 1; k >= 0 && topLayer < 0; --k)
        if (!regions[k].empty()) topLayer = k;
    nlohmann::json layers = nlohmann::json::array(), top = nlohmann::json::object();
    ExposureError total;
    for (int k = 0; k < int(regions.size()); ++k) {
        if (regions[k].empty()) continue;
        ExposureError& e = errors[k];
        if (e.cells > 0) e.rmsRelative = std::sqrt(e.sse / e.cells) / targetDose;
        nlohmann::json row{{"layer", k},
                           {"sse_mJ2_per_mm4", e.sse},
                           {"rms_over_Etar", e.rmsRelative},
                           {"max_over_Etar", e.maxRelative}};
        if (k == topLayer) top = row;
        layers.push_back(row);
        addSums(total, e);
    }
    if (total.cells > 0) total.rmsRelative = std::sqrt(total.sse / total.cells) / targetDose;
    if (all) {
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

}  // namespace vpsim::optimise::detail
