#include "vpsim/validate/surface_deviation.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"

namespace vpsim::validate {

std::vector<float> vertexDeviations(const geometry::Mesh& cured,
                                    const geometry::LevelSet& reference) {
    std::vector<float> deviations;
    reference.sample(cured.vertices, deviations);
    return deviations;
}

SurfaceDeviation measureSurfaceDeviation(const geometry::Mesh& cured,
                                         const geometry::LevelSet& reference) {
    if (cured.vertices.empty()) throw InputError("nothing cured: the cured surface is empty");
    return summarizeDeviations(vertexDeviations(cured, reference), reference.halfWidth());
}

SurfaceDeviation summarizeDeviations(const std::vector<float>& d, double bandHalfWidth) {
    if (d.empty()) throw InputError("nothing cured: the cured surface is empty");
    SurfaceDeviation out;
    out.samples = d.size();
    const double band = bandHalfWidth * (1.0 - 1e-6);
    double sum = 0, sumSq = 0;
    std::vector<float> magnitude(d.size());
    for (size_t i = 0; i < d.size(); ++i) {
        sum += d[i];
        sumSq += double(d[i]) * d[i];
        magnitude[i] = std::abs(d[i]);
        out.beyondBand += magnitude[i] >= band;
    }
    out.mean = sum / double(d.size());
    out.rms = std::sqrt(sumSq / double(d.size()));
    size_t rank = size_t(std::ceil(0.95 * double(d.size()))) - 1;
    std::nth_element(magnitude.begin(), magnitude.begin() + rank, magnitude.end());
    out.p95 = magnitude[rank];
    out.max = *std::max_element(magnitude.begin(), magnitude.end());
    return out;
}

nlohmann::json SurfaceDeviation::toJson() const {
    return {{"mean", mean}, {"rms", rms},         {"p95", p95},
            {"max", max},   {"samples", samples}, {"beyond_band", beyondBand}};
}

}  // namespace vpsim::validate
