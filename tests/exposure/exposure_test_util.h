#pragma once
// Helpers shared by the exposure tests.

#include <functional>
#include <random>
#include <vector>

#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::test {

/// Runs an engine (ExposureEngine or TabulatedExposureEngine) and keeps every slice,
/// [layer][slice].
template <class Engine>
std::vector<std::vector<exposure::SurfaceGrid>> exposeAll(Engine& engine,
                                                          const plan::ScanPlan& plan) {
    std::vector<std::vector<exposure::SurfaceGrid>> slices(
        plan.layers.size(), std::vector<exposure::SurfaceGrid>(engine.grid().slicesPerLayer));
    engine.run(plan,
               [&](const exposure::ExposureSlice& s) { slices[s.layer][s.slice] = *s.values; });
    return slices;
}

/// `layers` layers of thickness h, each with 3 random vectors and a random point within
/// [-extent, extent]^2 (mm), powers 1..20 mW at 500 mm/s.
inline plan::ScanPlan randomPlan(int layers, double h, unsigned seed, double extent = 0.3) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(-extent, extent), power(1.0, 20.0);
    plan::ScanPlan plan;
    plan.machine.layerThickness = h;
    for (int k = 0; k < layers; ++k) {
        plan::LayerPlan layer;
        layer.z = (k + 1) * h;
        for (int v = 0; v < 3; ++v)
            layer.vectors.push_back({pos(rng), pos(rng), pos(rng), pos(rng), power(rng), 500.0});
        layer.points.push_back({pos(rng), pos(rng), 0.01 * power(rng)});
        plan.layers.push_back(layer);
    }
    return plan;
}

/// A kernel table filled at its bin centres from intensity(r, z) (mW/mm^2).
inline kernel::BeamKernel tableKernel(double power, double rBin, uint32_t rBins, double zBin,
                                      uint32_t zBins,
                                      const std::function<double(double, double)>& intensity) {
    kernel::BeamKernel k;
    k.power = power;
    k.rBin = rBin;
    k.zBin = zBin;
    k.rBins = rBins;
    k.zBins = zBins;
    k.intensity.resize(size_t(rBins) * zBins);
    for (uint32_t iz = 0; iz < zBins; ++iz)
        for (uint32_t ir = 0; ir < rBins; ++ir)
            k.intensity[size_t(iz) * rBins + ir] =
                float(intensity((ir + 0.5) * rBin, (iz + 0.5) * zBin));
    return k;
}

/// Exposure is linear in the plan: doubling every power doubles it, and two plans run together
/// give the sum of each run alone. Checks every `stride`-th cell of every slice of `layers`
/// random layers within [-extent, extent]^2. Tolerance: float rounding, 1e-5 relative.
inline void requireSuperposition(exposure::ExposureModel& engine, int layers, double extent,
                                 size_t stride) {
    const double h = engine.layerThickness();
    plan::ScanPlan a = randomPlan(layers, h, 11, extent), b = randomPlan(layers, h, 12, extent),
                   sum = a, doubled = a;
    for (int k = 0; k < layers; ++k) {
        for (const auto& v : b.layers[k].vectors) sum.layers[k].vectors.push_back(v);
        for (const auto& p : b.layers[k].points) sum.layers[k].points.push_back(p);
        for (auto& v : doubled.layers[k].vectors) v.power *= 2;
        for (auto& p : doubled.layers[k].points) p.energy *= 2;
    }
    auto ea = exposeAll(engine, a), eb = exposeAll(engine, b), es = exposeAll(engine, sum),
         ed = exposeAll(engine, doubled);
    for (int k = 0; k < layers; ++k)
        for (size_t s = 0; s < ea[k].size(); ++s)
            for (size_t c = 0; c < ea[k][s].values.size(); c += stride) {
                CHECK(es[k][s].values[c] ==
                      Approx(ea[k][s].values[c] + eb[k][s].values[c]).epsilon(1e-5).margin(1e-7));
                CHECK(ed[k][s].values[c] ==
                      Approx(2 * ea[k][s].values[c]).epsilon(1e-5).margin(1e-7));
            }
}

}  // namespace vpsim::test
