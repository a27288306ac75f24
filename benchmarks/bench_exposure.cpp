// Exposure of a 10 x 10 x 5 mm block at 10 um voxels (~5e8 voxels): ACES hatching on every 50 um
// layer, the separable engine with print-through, and sparse OpenVDB storage of the result.
// Prints JSON: seconds per stage, voxels per second, peak memory, and the ratio to the
// memory-bandwidth floor (touching every voxel's 4 bytes once at ~30 GB/s, docs/PLATFORM.md), plus
// both engines' CPU and shader paths measured in the same run, back to back, on a slab of 10
// layers: cpu_ns_per_voxel and shader_ns_per_voxel keyed "fitted" / "tabulated" (the engine's wall
// time over the whole slab per voxel, upload, dispatch, readback and the slices' hand-over
// included, the deposit's time taken out: engine_timing.h; the best of `repeats` alternating runs
// of each path, so drift of the shared machine hits both), and the same with the deposit
// (*_with_deposit). Each engine's construction (stencils, shader pipelines) is timed on its own
// (cpu_setup_seconds, shader_setup_seconds), and the shader's first run, before the timed ones
// (shader_first_run_seconds: what a small job pays once).
//
// bench_exposure [engines] [--repeats N] [--side MM] [--engine NAME]: "engines" runs only the
// engine comparison (of one engine with --engine), on a slab of side MM (default 10).
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/exposure/dose_volume.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/exposure/tabulated_engine.h"
#include "vpsim/gpu/context.h"
#include "vpsim/plan/aces/aces.h"

#include "engine_timing.h"

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

/// Eq. 12 tabulated like a Monte Carlo kernel (2.5 um radial bins to 0.2 mm, 4.46 um depth bins
/// to 0.36 mm) with the default job's fitted We3D = 63.5 um and De3D = 36.6 um: the tabulated
/// engine then builds the stencils of the default job's kernel (about 23 depths, 8-10 cells).
kernel::BeamKernel defaultLikeKernel(double power) {
    const double W = 0.0635, De = 0.0366, pi = 3.14159265358979323846;
    kernel::BeamKernel k;
    k.power = power;
    k.rBin = 0.0025;
    k.zBin = 0.0044625;
    k.rBins = 80;
    k.zBins = 80;
    k.intensity.resize(size_t(k.rBins) * k.zBins);
    for (uint32_t iz = 0; iz < k.zBins; ++iz)
        for (uint32_t ir = 0; ir < k.rBins; ++ir) {
            double r = (ir + 0.5) * k.rBin, z = (iz + 0.5) * k.zBin;
            k.intensity[size_t(iz) * k.rBins + ir] =
                float(2 * power / (pi * W * W) * std::exp(-2 * r * r / (W * W) - z / De));
        }
    return k;
}

double peakMemoryGiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024.0 / 1024.0;
}

double seconds(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The 100-layer block on the CPU fitted engine with OpenVDB storage.
void blockFigures(nlohmann::json& out, const exposure::ExposureGrid& grid,
                  const kernel::FittedBeam& beam, const plan::ScanPlan& plan, double h) {
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
}

using EngineFactory =
    std::function<std::unique_ptr<exposure::ExposureModel>(std::shared_ptr<gpu::Context>)>;

/// ns per voxel of the CPU and shader paths of one engine on `slab` (engine_timing.h); the engines
/// are built outside the timing (stencils, pipelines).
void compareEngine(nlohmann::json& out, const std::string& name, const EngineFactory& make,
                   const plan::ScanPlan& slab, const std::shared_ptr<gpu::Context>& context,
                   int repeats) {
    auto start = std::chrono::steady_clock::now();
    auto cpu = make(nullptr);
    out["cpu_setup_seconds"][name] = bench::secondsSince(start);
    const double voxels = bench::slabVoxels(cpu->grid(), slab);
    std::vector<exposure::ExposureModel*> engines{cpu.get()};
    std::unique_ptr<exposure::ExposureModel> shader;
    if (context) {
        start = std::chrono::steady_clock::now();
        shader = make(context);
        out["shader_setup_seconds"][name] = bench::secondsSince(start);
        out["shader_first_run_seconds"][name] = bench::firstRunSeconds(*shader, slab);
        engines.push_back(shader.get());
    }
    const bench::EngineTimes t = bench::timeEngines(engines, slab, repeats);
    const double bestCpu = t.runs[0] - t.deposit;
    out["slab_voxels"][name] = voxels;
    out["deposit_ns_per_voxel"][name] = t.deposit / voxels * 1e9;
    out["cpu_ns_per_voxel"][name] = bestCpu / voxels * 1e9;
    out["cpu_ns_per_voxel_with_deposit"][name] = t.runs[0] / voxels * 1e9;
    if (!shader) return;
    const double bestShader = t.runs[1] - t.deposit;
    out["shader_ns_per_voxel"][name] = bestShader / voxels * 1e9;
    out["shader_ns_per_voxel_with_deposit"][name] = t.runs[1] / voxels * 1e9;
    out["shader_over_cpu"][name] = bestShader / bestCpu;
    // The same from process CPU time (every thread's): the work, apart from waits for a core.
    out["cpu_path_cpu_ns_per_voxel"][name] = (t.cpuRuns[0] - t.cpuDeposit) / voxels * 1e9;
    out["shader_path_cpu_ns_per_voxel"][name] = (t.cpuRuns[1] - t.cpuDeposit) / voxels * 1e9;
    out["shader_over_cpu_in_cpu_time"][name] =
        (t.cpuRuns[1] - t.cpuDeposit) / (t.cpuRuns[0] - t.cpuDeposit);
}

}  // namespace

int main(int argc, char** argv) {
    bool enginesOnly = false;
    int repeats = 3;
    double slabSide = 10.0;
    std::string only;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "engines") == 0)
            enginesOnly = true;
        else if (std::strcmp(argv[i], "--repeats") == 0 && i + 1 < argc)
            repeats = std::max(1, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--side") == 0 && i + 1 < argc)
            slabSide = std::atof(argv[++i]);
        else if (std::strcmp(argv[i], "--engine") == 0 && i + 1 < argc)
            only = argv[++i];
        else {
            std::cerr << "usage: bench_exposure [engines] [--repeats N] [--side MM] [--engine "
                         "fitted|tabulated]\n";
            return 2;
        }
    }
    const double h = 0.05, pitch = 0.01, side = 10.0, hs = 0.025, power = 10.0, speed = 400.0;
    const kernel::FittedBeam beam{0.05, 0.12};
    nlohmann::json out{{"benchmark", "exposure"}, {"part_mm", {side, side, 5.0}}, {"voxel_um", 10}};
    try {
        exposure::ExposureGrid grid =
            exposure::ExposureGrid::covering(0, 0, side, side, 0.1, pitch, 5);
        if (!enginesOnly)
            blockFigures(out, grid, beam, acesBlock(100, h, side, hs, power, speed), h);

        // Both engines, CPU vs shaders (the default Vulkan device), on 10 layers of a slab.
        std::shared_ptr<gpu::Context> context;
        try {
            context = gpu::Context::create();
            out["device"] = context->info().name;
        } catch (const Error& e) {
            out["vulkan_error"] = e.what();
        }
        const plan::ScanPlan slab = acesBlock(10, h, slabSide, hs, power, speed);
        const exposure::ExposureGrid slabGrid =
            exposure::ExposureGrid::covering(0, 0, slabSide, slabSide, 0.1, pitch, 5);
        out["slab_mm"] = {slabSide, slabSide, 10 * h};
        out["repeats"] = repeats;
        if (only != "tabulated")
            compareEngine(
                out, "fitted",
                [&](std::shared_ptr<gpu::Context> c) {
                    return std::make_unique<exposure::ExposureEngine>(slabGrid, beam, h, c);
                },
                slab, context, repeats);
        const kernel::BeamKernel table = defaultLikeKernel(power);
        {
            exposure::TabulatedExposureEngine probe(slabGrid, table, h);
            size_t taps = 0;
            for (const auto& st : probe.stencils())
                for (float w : st.weights) taps += w != 0.0f;
            out["tabulated_stencils"] = {{"depths", probe.stencils().size()},
                                         {"largest_half_width", probe.stencils().front().halfWidth},
                                         {"non_zero_taps", taps}};
        }
        if (only != "fitted")
            compareEngine(
                out, "tabulated",
                [&](std::shared_ptr<gpu::Context> c) {
                    return std::make_unique<exposure::TabulatedExposureEngine>(slabGrid, table, h,
                                                                               c);
                },
                slab, context, repeats);
    } catch (const Error& e) {
        out["error"] = e.what();
    }
    std::cout << out.dump(2) << std::endl;
    return 0;
}
