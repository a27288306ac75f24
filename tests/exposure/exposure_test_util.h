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

}  // namespace vpsim::test
