// Exposure of a 10 x 10 x 5 mm block at 10 um voxels (~5e8 voxels): ACES hatching on every 50 um
// layer, the separable engine with print-through, and sparse OpenVDB storage of the result.
// Prints JSON: seconds per stage, voxels per second, peak memory, and the ratio to the
// memory-bandwidth floor (touching every voxel's 4 bytes once at ~30 GB/s, docs/PLATFORM.md), plus
// the Vulkan (lavapipe) and CPU engine paths measured in the same run on a 10-layer slab.
#include <sys/resource.h>

#include <chrono>
#include <iostream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/exposure/dose_volume.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/gpu/context.h"
#include "vpsim/plan/aces/aces.h"

namespace {

using namespace vpsim;

/// `layers` layers of the square [0, side]^2 hatched along x at spacing hs (plan::hatchRegion).
plan::ScanPlan acesBlock(int layers, double h, double side, double hs, double power, double speed) {
    plan::ScanPlan plan;
    plan.machine.layerThickness = h;
    const geometry::PolygonSet square = geometry::PolygonSet::rectangle({0, 0}, {side, side});
    for (int k = 0; k < layers; ++k) {
        plan::LayerPlan layer;
        layer.z = (k + 1) * h;
        layer.vectors = plan::hatchRegion(square, hs, 0.0, power, speed);
        plan.layers.push_back(layer);
    }
    return plan;
}

double peakMemoryGiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024.0 / 1024.0;
}

double seconds(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main() {
    const double h = 0.05, pitch = 0.01, side = 10.0, hs = 0.025, power = 10.0, speed = 400.0;
    const kernel::FittedBeam beam{0.05, 0.12};
    nlohmann::json out{{"benchmark", "exposure"}, {"part_mm", {side, side, 5.0}}, {"voxel_um", 10}};
    try {
        exposure::ExposureGrid grid =
            exposure::ExposureGrid::covering(0, 0, side, side, 0.1, pitch, 5);
        plan::ScanPlan plan = acesBlock(100, h, side, hs, power, speed);
        const double voxels = double(grid.nx) * grid.ny * grid.slicesPerLayer * plan.layers.size();
        exposure::ExposureEngine engine(grid, beam, h);
        exposure::DoseVolume volume(grid, h / grid.slicesPerLayer, 0.0, 0.05f);
        double sinkSeconds = 0;
        auto start = std::chrono::steady_clock::now();
        double engineSeconds = engine.run(plan, [&](const exposure::ExposureSlice& s) {
            auto t = std::chrono::steady_clock::now();
            volume.add(s);
            sinkSeconds += seconds(t);
        });
        double total = seconds(start);
        out["voxels"] = voxels;
        out["cpu_engine_seconds"] = engineSeconds;
        out["vdb_store_seconds"] = sinkSeconds;
        out["deposit_and_other_seconds"] = total - engineSeconds - sinkSeconds;
        out["expose_total_seconds"] = total;
        out["voxels_per_second"] = voxels / total;
        out["vdb_active_voxels"] = volume.activeVoxels();
        out["vdb_memory_GiB"] = double(volume.memoryBytes()) / (1u << 30);
        out["memory_floor_seconds"] = voxels * 4 / 30e9;
        out["ratio_to_memory_floor"] = total / (voxels * 4 / 30e9);
        out["peak_memory_GiB"] = peakMemoryGiB();

        // Same engine, CPU vs Vulkan, on the first 10 layers.
        plan::ScanPlan slab = acesBlock(10, h, side, hs, power, speed);
        auto sinkNothing = [](const exposure::ExposureSlice&) {};
        exposure::ExposureEngine cpu(grid, beam, h);
        auto t = std::chrono::steady_clock::now();
        cpu.run(slab, sinkNothing);
        out["cpu_seconds_per_layer"] = seconds(t) / 10;
        try {
            exposure::ExposureEngine gpu(grid, beam, h, gpu::Context::create());
            t = std::chrono::steady_clock::now();
            gpu.run(slab, sinkNothing);
            out["vulkan_seconds_per_layer"] = seconds(t) / 10;
            out["vulkan_over_cpu_speed"] =
                out["cpu_seconds_per_layer"].get<double>() / (seconds(t) / 10);
        } catch (const Error& e) {
            out["vulkan_error"] = e.what();
        }
    } catch (const Error& e) {
        out["error"] = e.what();
    }
    std::cout << out.dump(2) << std::endl;
    return 0;
}
