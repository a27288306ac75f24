#include "vpsim/optimise/dlp/part.h"

#include <chrono>
#include <mutex>
#include <string>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"

namespace vpsim::optimise {

DlpObjective dlpObjectiveFromName(const std::string& name) {
    if (name == "conversion-l2") return DlpObjective::ConversionL2;
    if (name == "geometric") return DlpObjective::Geometric;
    throw InputError("unknown DLP objective '" + name + "' (known: conversion-l2, geometric)");
}

Bonding bondingFromName(const std::string& name) {
    if (name == "own-layer") return Bonding::OwnLayer;
    if (name == "run-bottom") return Bonding::RunBottom;
    throw InputError("unknown bonding '" + name + "' (known: own-layer, run-bottom)");
}

std::vector<uint8_t> columnProfile(const DlpLayerStack& part, int x, int y) {
    std::vector<uint8_t> profile(part.layers.size());
    const size_t pixel = size_t(y) * size_t(part.width) + size_t(x);
    for (size_t k = 0; k < part.layers.size(); ++k) profile[k] = part.layers[k][pixel] ? 1 : 0;
    return profile;
}

std::vector<double> columnDoses(const DlpPartResult& result, int x, int y) {
    std::vector<double> d(result.dose.size());
    const size_t pixel = size_t(y) * size_t(result.width) + size_t(x);
    for (size_t k = 0; k < d.size(); ++k) d[k] = result.dose[k][pixel];
    return d;
}

DlpPartResult optimiseDlpPart(const DlpLayerStack& part, const DlpPartOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const size_t pixels = size_t(part.width) * size_t(part.height);
    for (const auto& layer : part.layers)
        if (layer.size() != pixels)
            throw InputError("DLP part: every layer mask must have width x height pixels");
    // Group the pixels by solid profile (the profile bytes are the key).
    std::unordered_map<std::string, size_t> index;
    std::vector<std::string> profiles;
    std::vector<uint32_t> profileOf(pixels, UINT32_MAX);
    std::string key(part.layers.size(), '\0');
    for (size_t p = 0; p < pixels; ++p) {
        bool any = false;
        for (size_t k = 0; k < part.layers.size(); ++k) {
            key[k] = part.layers[k][p] ? 1 : 0;
            any = any || key[k];
        }
        if (!any) continue;  // empty column: no light
        auto [it, inserted] = index.emplace(key, profiles.size());
        if (inserted) profiles.push_back(key);
        profileOf[p] = uint32_t(it->second);
    }
    std::vector<std::vector<float>> solved(profiles.size());
    std::vector<double> gaps(profiles.size(), 0.0);
    std::mutex errorMutex;
    std::string firstError;
    Progress progress(options.objective == DlpObjective::Geometric
                          ? "DLP masks: geometric optimum of each distinct column"
                          : "DLP masks: exact optimum of each distinct column",
                      profiles.size());
    tbb::parallel_for(size_t(0), profiles.size(), [&](size_t i) {
        try {
            std::vector<uint8_t> solid(profiles[i].begin(), profiles[i].end());
            std::vector<double> dose;
            if (options.objective == DlpObjective::Geometric) {
                DlpGeometricResult r =
                    optimiseColumnGeometric(solid, options.problem, options.geometric);
                dose = std::move(r.dose);
                gaps[i] = r.gap;  // 0 when enumerated; else against the structural bound
            } else {
                DlpSearchResult r = solveColumnExactly(solid, options.problem, options.search);
                dose = std::move(r.best.dose);
                gaps[i] = r.gap;
            }
            solved[i].assign(dose.begin(), dose.end());
            progress.advance();
        } catch (const std::exception& e) {
            std::lock_guard<std::mutex> lock(errorMutex);
            if (firstError.empty()) firstError = e.what();
        }
    });
    if (!firstError.empty()) throw InputError(firstError);
    DlpPartResult out;
    out.width = part.width;
    out.height = part.height;
    out.distinctColumns = profiles.size();
    out.dose.assign(part.layers.size(), std::vector<float>(pixels, 0.0f));
    for (size_t p = 0; p < pixels; ++p) {
        if (profileOf[p] == UINT32_MAX) continue;
        const std::vector<float>& d = solved[profileOf[p]];
        for (size_t k = 0; k < d.size(); ++k) out.dose[k][p] = d[k];
    }
    for (double g : gaps) {
        out.maxGap = std::max(out.maxGap, g);
        out.meanGap += g / double(std::max<size_t>(gaps.size(), 1));
        out.openColumns += g > 1e-9 ? 1 : 0;
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace vpsim::optimise
