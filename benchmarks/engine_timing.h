#pragma once
// How bench_exposure and bench_pipeline time an exposure engine per voxel: the wall time of a
// whole run of a slab (on the shader path upload, dispatch, readback and the slices' hand-over to
// a sink that does nothing included) on deposits computed beforehand, so the figure is the
// engine's own: each layer's fill is a copy of its deposit (a memcpy of the grid, the same on both
// paths). Before, the engine's time was a run's less the deposit's (the same CPU code on both
// paths, 5-10x the fitted engine's cost), and on the shared machine the two minima's noise
// swamped the fitted engine's figure (it could turn negative). The deposit is still timed on its
// own; EngineTimes::runs is the engine's best plus the deposit's best, as a run with its deposit
// would take, so that runs - deposit is the engine's time. Best of `repeats` runs, the paths
// alternating so that drift of the shared machine hits both. Each run's process CPU time (every
// thread's, lavapipe's included) is kept too: on a loaded machine it shows the work apart from the
// waits for a core.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstring>
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

/// Every layer's deposit on `grid`, as ExposureModel::run makes them.
inline std::vector<exposure::SurfaceGrid> layerDeposits(const exposure::ExposureGrid& grid,
                                                        const plan::ScanPlan& plan) {
    std::vector<exposure::SurfaceGrid> deposits;
    for (const plan::LayerPlan& layer : plan.layers) {
        deposits.push_back(grid.surface());
        exposure::depositLayer(layer, deposits.back());
    }
    return deposits;
}

/// Reaches ExposureModel::forward (protected), the layer loop of run(), to run an engine on
/// deposits made beforehand.
struct ForwardAccess : exposure::ExposureModel {
    static double replay(exposure::ExposureModel& engine,
                         const std::vector<exposure::SurfaceGrid>& deposits,
                         const plan::ScanPlan& plan) {
        auto forward = &ForwardAccess::forward;
        return (engine.*forward)(
            int(deposits.size()),
            [&](int k, exposure::SurfaceGrid& deposit) {
                std::memcpy(deposit.values.data(), deposits[k].values.data(),
                            deposit.values.size() * sizeof(float));
            },
            [&](int k) { return plan.layers[k].z; }, [](const exposure::ExposureSlice&) {});
    }
};

/// Wall seconds of the engine's run of `plan` on its deposits, the slices handed to a sink that
/// does nothing.
inline double runSeconds(exposure::ExposureModel& engine,
                         const std::vector<exposure::SurfaceGrid>& deposits,
                         const plan::ScanPlan& plan) {
    const auto start = std::chrono::steady_clock::now();
    ForwardAccess::replay(engine, deposits, plan);
    return secondsSince(start);
}

/// Wall seconds of one run of `plan`, deposits included, right after the engine is made: the
/// first dispatches' costs (on a GPU, first use of the pipeline and buffers) on top of a run's.
inline double firstRunSeconds(exposure::ExposureModel& engine, const plan::ScanPlan& plan) {
    const auto start = std::chrono::steady_clock::now();
    engine.run(plan, [](const exposure::ExposureSlice&) {});
    return secondsSince(start);
}

/// Best-of times of the engines on the plan's deposits and of the deposit alone, wall and process
/// CPU; runs and cpuRuns add the deposit's best to each engine's (see the top of this file).
struct EngineTimes {
    std::vector<double> runs;     ///< wall, per engine, in the order given
    std::vector<double> cpuRuns;  ///< CPU seconds, per engine
    double deposit = 1e300, cpuDeposit = 1e300;
};

inline EngineTimes timeEngines(const std::vector<exposure::ExposureModel*>& engines,
                               const plan::ScanPlan& plan, int repeats) {
    EngineTimes times;
    std::vector<double> engine(engines.size(), 1e300), cpuEngine(engines.size(), 1e300);
    const std::vector<exposure::SurfaceGrid> deposits = layerDeposits(engines[0]->grid(), plan);
    for (int r = 0; r < repeats; ++r) {
        double cpu = processCpuSeconds();
        times.deposit = std::min(times.deposit, depositSeconds(engines[0]->grid(), plan));
        times.cpuDeposit = std::min(times.cpuDeposit, processCpuSeconds() - cpu);
        for (size_t e = 0; e < engines.size(); ++e) {
            cpu = processCpuSeconds();
            engine[e] = std::min(engine[e], runSeconds(*engines[e], deposits, plan));
            cpuEngine[e] = std::min(cpuEngine[e], processCpuSeconds() - cpu);
        }
    }
    for (size_t e = 0; e < engines.size(); ++e) {
        times.runs.push_back(engine[e] + times.deposit);
        times.cpuRuns.push_back(cpuEngine[e] + times.cpuDeposit);
    }
    return times;
}

/// Voxels of a run of `plan` on `grid`.
inline double slabVoxels(const exposure::ExposureGrid& grid, const plan::ScanPlan& plan) {
    return double(grid.nx) * grid.ny * grid.slicesPerLayer * double(plan.layers.size());
}

}  // namespace vpsim::bench
