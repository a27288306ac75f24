#pragma once
// How bench_exposure and bench_pipeline time an exposure engine per voxel: the wall time of a
// whole run of a slab (on the shader path upload, dispatch, readback and the slices' hand-over to
// a sink that does nothing included) less the time of depositing its layers, the same CPU code on
// both paths, so the figure is the engine's own. Best of `repeats` runs, the paths alternating so
// that drift of the shared machine hits both. The deposit's best time is subtracted from each
// path's best run: on a heavily loaded machine (load 20 on 2 cores) the two minima can come from
// different luck and the fitted engine's small figure can even turn negative; its CPU-time
// figures below are then the ones to read. Each run's process CPU time (every thread's,
// lavapipe's included) is kept too: on a loaded machine it shows the work apart from the waits for
// a core.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_model.h"

namespace vpsim::bench {

inline double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// CPU seconds (user + system) of every thread of this process so far.
inline double processCpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

/// Wall seconds of depositing every layer of `plan` on `grid`, as ExposureModel::run does.
inline double depositSeconds(const exposure::ExposureGrid& grid, const plan::ScanPlan& plan) {
    exposure::SurfaceGrid deposit = grid.surface();
    const auto start = std::chrono::steady_clock::now();
    for (const plan::LayerPlan& layer : plan.layers) {
        std::fill(deposit.values.begin(), deposit.values.end(), 0.0f);
        exposure::depositLayer(layer, deposit);
    }
    return secondsSince(start);
}

/// Wall seconds of engine.run(plan), the slices handed to a sink that does nothing.
inline double runSeconds(exposure::ExposureModel& engine, const plan::ScanPlan& plan) {
    const auto start = std::chrono::steady_clock::now();
    engine.run(plan, [](const exposure::ExposureSlice&) {});
    return secondsSince(start);
}

/// Best-of times of the engines (run seconds, deposit included) and of the deposit alone, wall
/// and process CPU.
struct EngineTimes {
    std::vector<double> runs;     ///< wall, per engine, in the order given
    std::vector<double> cpuRuns;  ///< CPU seconds, per engine
    double deposit = 1e300, cpuDeposit = 1e300;
};

inline EngineTimes timeEngines(const std::vector<exposure::ExposureModel*>& engines,
                               const plan::ScanPlan& plan, int repeats) {
    EngineTimes times;
    times.runs.assign(engines.size(), 1e300);
    times.cpuRuns.assign(engines.size(), 1e300);
    for (int r = 0; r < repeats; ++r) {
        double cpu = processCpuSeconds();
        times.deposit = std::min(times.deposit, depositSeconds(engines[0]->grid(), plan));
        times.cpuDeposit = std::min(times.cpuDeposit, processCpuSeconds() - cpu);
        for (size_t e = 0; e < engines.size(); ++e) {
            cpu = processCpuSeconds();
            times.runs[e] = std::min(times.runs[e], runSeconds(*engines[e], plan));
            times.cpuRuns[e] = std::min(times.cpuRuns[e], processCpuSeconds() - cpu);
        }
    }
    return times;
}

/// Voxels of a run of `plan` on `grid`.
inline double slabVoxels(const exposure::ExposureGrid& grid, const plan::ScanPlan& plan) {
    return double(grid.nx) * grid.ny * grid.slicesPerLayer * double(plan.layers.size());
}

}  // namespace vpsim::bench
