// CPU path of the photon Monte Carlo: the physics of shaders/include/photon_step.glsl compiled as
// C++, photons spread over threads with TBB. Each photon has its own random stream, and tallies
// are integer sums, so the result does not depend on the thread count or the scheduling. The step
// is compiled once per estimator (mc_cpu_trace.inc), as the shader specialises it.

#include <algorithm>
#include <chrono>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "photon_params.h"
#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"
#include "vpsim/transport/beam_convolution.h"

namespace vpsim::glsl {
namespace {  // internal linkage: GCC inlines the step's functions called once into the loop
#include "rng.glsl"
// The phase table and tallies of the run in progress on this thread (set by each task before
// tracing): the hooks photon_step.glsl calls.
thread_local const float* tPhaseTable = nullptr;
thread_local uint64_t* tBins = nullptr;  // (r,z) bins, batch-major when kept per batch
thread_local uint64_t* tVoxels = nullptr;
thread_local uint32_t tBatchStride = 0;  // bins per batch copy; 0 = one shared copy
inline float photonPhaseTable(int i) {
    return tPhaseTable[i];
}
// (r,z) additions are queued and made in runs of BIN_QUEUE, outside the step's chain of
// dependent arithmetic: the collision estimator adds at every interaction, and queued it runs at
// 18.2-18.7 M interactions per CPU-second against 16.6-16.9 adding in place (bench_photon_mc).
// Queued indices include the batch offset (below MAX_RZ_BINS, so 32 bits hold them).
constexpr int BIN_QUEUE = 256;
thread_local uint32_t tQueuedBin[BIN_QUEUE];
thread_local uint64_t tQueuedQuanta[BIN_QUEUE];
thread_local int tQueued = 0;
inline void flushBins() {
    for (int i = 0; i < tQueued; ++i) tBins[tQueuedBin[i]] += tQueuedQuanta[i];
    tQueued = 0;
}
inline void photonAddBin(uint batch, uint bin, uint64_t quanta) {
    tQueuedBin[tQueued] = batch * tBatchStride + bin;
    tQueuedQuanta[tQueued] = quanta;
    if (++tQueued == BIN_QUEUE) flushBins();
}
inline void photonAddVoxel(uint voxel, uint64_t quanta) {
    tVoxels[voxel] += quanta;
}
}  // namespace
}  // namespace vpsim::glsl

#define VPSIM_MC_NAMESPACE analog
#define VPSIM_MC_ESTIMATOR PHOTON_ESTIMATOR_ANALOG
#include "mc_cpu_trace.inc"
#define VPSIM_MC_NAMESPACE implicit
#define VPSIM_MC_ESTIMATOR PHOTON_ESTIMATOR_IMPLICIT
#include "mc_cpu_trace.inc"
#define VPSIM_MC_NAMESPACE implicit_track
#define VPSIM_MC_ESTIMATOR PHOTON_ESTIMATOR_IMPLICIT_TRACK
#include "mc_cpu_trace.inc"
#define VPSIM_MC_NAMESPACE track
#define VPSIM_MC_ESTIMATOR PHOTON_ESTIMATOR_TRACK
#include "mc_cpu_trace.inc"
#define VPSIM_MC_NAMESPACE collision
#define VPSIM_MC_ESTIMATOR PHOTON_ESTIMATOR_COLLISION
#include "mc_cpu_trace.inc"

namespace vpsim::transport {

namespace {

/// One thread's share of the tallies.
struct LocalTally {
    std::array<BatchTally, MC_BATCHES> batches{};
    std::vector<ControlTally> controls;
    std::vector<uint64_t> rz, grid;
    LocalTally(size_t rzBins, size_t voxels, bool controlled)
        : controls(controlled ? MC_CONTROL_BATCHES : 0), rz(rzBins, 0), grid(voxels, 0) {}
};

using TraceFunction = void (*)(const glsl::PhotonParams&, uint64_t, uint64_t, uint32_t, BatchTally&,
                               ControlTally*);

/// The step loop compiled for the run's estimator.
TraceFunction traceFor(const glsl::PhotonParams& p) {
    switch (p.estimator & 255u) {
        case glsl::PHOTON_ESTIMATOR_ANALOG: return glsl::analog::tracePhotons;
        case glsl::PHOTON_ESTIMATOR_IMPLICIT: return glsl::implicit::tracePhotons;
        case glsl::PHOTON_ESTIMATOR_IMPLICIT_TRACK: return glsl::implicit_track::tracePhotons;
        case glsl::PHOTON_ESTIMATOR_TRACK: return glsl::track::tracePhotons;
        case glsl::PHOTON_ESTIMATOR_COLLISION: return glsl::collision::tracePhotons;
    }
    throw Error("photon Monte Carlo: unknown estimator " + std::to_string(p.estimator & 255u));
}

/// The first photon offset >= begin whose index (firstPhoton + offset) is in batch b.
uint64_t firstOfBatch(uint64_t begin, uint64_t b, const McSetup& setup) {
    const uint64_t batchOfBegin = (setup.firstPhoton + begin) % MC_BATCHES;
    return begin + (b + MC_BATCHES - batchOfBegin) % MC_BATCHES;
}

}  // namespace

McResult runPhotonMcCpu(const McSetup& setup, int threads) {
    validateSetup(setup);
    if (convolvesBeam(setup))
        return convolveBeam(runPhotonMcCpu(pencilSetup(setup), threads), setup);
    const glsl::PhotonParams params = makePhotonParams(setup);
    const TraceFunction trace = traceFor(params);
    const std::vector<float> table = makePhaseTable(setup);
    const size_t rzBins = size_t(setup.bins.rBins) * setup.bins.zBins;
    const size_t rzWords = setup.binsPerBatch ? rzBins * MC_BATCHES : rzBins;
    const size_t voxels = size_t(params.gridNxy) * params.gridNxy * params.gridNz;

    auto start = std::chrono::steady_clock::now();
    McResult result;
    result.setup = setup;
    const bool controlled = result.controlled();
    tbb::enumerable_thread_specific<LocalTally> locals(
        [&] { return LocalTally(rzWords, voxels, controlled); });
    Progress progress("photon Monte Carlo (CPU)", setup.photons);
    // More threads than cores would only make TBB warn: clamp. TBB's count respects the CPU
    // affinity mask (an MPI rank bound to its cores), the hardware count would not.
    const int cores = std::max(1, tbb::info::default_concurrency());
    threads = threads > 0 ? std::min(threads, cores) : cores;
    tbb::task_arena arena(threads);
    // With a copy of the bins per batch, a task traces at least 512 photons of each batch, so
    // that a batch's copy is fetched into cache once per 512 photons rather than once per 32.
    const uint64_t grain = setup.binsPerBatch ? 512 * MC_BATCHES : 2048;
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<uint64_t>(0, setup.photons, grain),
                          [&](const tbb::blocked_range<uint64_t>& range) {
                              glsl::tPhaseTable = table.data();
                              LocalTally& local = locals.local();
                              glsl::tBins = local.rz.data();
                              glsl::tVoxels = local.grid.data();
                              glsl::tBatchStride = setup.binsPerBatch ? uint32_t(rzBins) : 0u;
                              // Batch by batch (photon i is in batch i % MC_BATCHES), so
                              // that consecutive photons add to the same copy of the bins.
                              for (uint64_t b = 0; b < MC_BATCHES; ++b) {
                                  const uint64_t i = firstOfBatch(range.begin(), b, setup);
                                  if (i >= range.end()) continue;
                                  const uint64_t first = setup.firstPhoton + i;
                                  const uint32_t batch = uint32_t(first % MC_BATCHES);
                                  trace(params, first, (range.end() - i - 1) / MC_BATCHES + 1,
                                        batch, local.batches[batch], local.controls.data());
                              }
                              glsl::flushBins();  // before another task sets tBins
                              progress.advance(range.size());
                          });
    });
    progress.finish();

    result.launchWeight = params.launchWeight;
    std::vector<uint64_t> rz(rzWords, 0);
    result.absorbedGrid.assign(voxels, 0);
    result.controlBatches.assign(controlled ? MC_CONTROL_BATCHES : 0, ControlTally{});
    for (const LocalTally& local : locals) {
        for (int b = 0; b < MC_BATCHES; ++b) result.batches[size_t(b)] += local.batches[size_t(b)];
        for (size_t c = 0; c < local.controls.size(); ++c)
            result.controlBatches[c] += local.controls[c];
        for (size_t i = 0; i < rzWords; ++i) rz[i] += local.rz[i];
        for (size_t i = 0; i < voxels; ++i) result.absorbedGrid[i] += local.grid[i];
    }
    setBins(result, std::move(rz), params);
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.backend = "cpu (" + std::to_string(threads) + " threads)";
    return result;
}

}  // namespace vpsim::transport
