// CPU path of the photon Monte Carlo: the physics of shaders/include/photon_step.glsl compiled as
// C++, photons spread over threads with TBB. Each photon has its own random stream, and tallies
// are integer sums, so the result does not depend on the thread count or the scheduling.

#include <algorithm>
#include <chrono>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "photon_params.h"
#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"
#include "vpsim/transport/beam_convolution.h"

namespace vpsim::glsl {
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
inline void photonAddBin(uint batch, uint bin, uint64_t quanta) {
    tBins[size_t(batch) * tBatchStride + bin] += quanta;
}
inline void photonAddVoxel(uint voxel, uint64_t quanta) {
    tVoxels[voxel] += quanta;
}
inline uint photonEstimator(const PhotonParams& p) {
    return p.estimator & 255u;
}
#include "photon_step.glsl"
}  // namespace vpsim::glsl

namespace vpsim::transport {

namespace {

/// One thread's share of the tallies.
struct LocalTally {
    std::array<BatchTally, MC_BATCHES> batches{};
    std::vector<uint64_t> rz, grid;
    LocalTally(size_t rzBins, size_t voxels) : rz(rzBins, 0), grid(voxels, 0) {}
};

void tracePhoton(const glsl::PhotonParams& p, const glsl::PhotonDerived& k, uint64_t index,
                 LocalTally& t) {
    glsl::PhotonState s;
    glsl::RngState rng;
    glsl::photonLaunch(p, uint32_t(index), uint32_t(index >> 32), s, rng);
    const uint32_t batch = uint32_t(index % MC_BATCHES);
    glsl::PhotonTally pt;
    glsl::photonTallyClear(pt);
    while (glsl::photonAdvance(p, k, s, rng, batch, pt)) {}
    BatchTally& b = t.batches[batch];
    b.photons += 1;
    b.specular += p.launchWeight - p.enteringWeight;
    b.diffuse += pt.diffuse;
    b.transmitted += pt.transmitted;
    b.absorbed += pt.absorbed;
    b.escaped += pt.escaped;
    b.scatterings += pt.scatterings;
    b.interactions += pt.interactions;
    b.rouletteGain += pt.rouletteGain;
    b.rouletteLoss += pt.rouletteLoss;
    b.absorbedWithin[0] += pt.within0;
    b.absorbedWithin[1] += pt.within1;
    b.absorbedWithin[2] += pt.within2;
    b.absorbedWithin[3] += pt.within3;
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
    const glsl::PhotonDerived derived = glsl::photonDerive(params);
    const std::vector<float> table = makePhaseTable(setup);
    const size_t rzBins = size_t(setup.bins.rBins) * setup.bins.zBins;
    const size_t rzWords = setup.binsPerBatch ? rzBins * MC_BATCHES : rzBins;
    const size_t voxels = size_t(params.gridNxy) * params.gridNxy * params.gridNz;

    auto start = std::chrono::steady_clock::now();
    tbb::enumerable_thread_specific<LocalTally> locals([&] { return LocalTally(rzWords, voxels); });
    Progress progress("photon Monte Carlo (CPU)", setup.photons);
    // More threads than cores would only make TBB warn: clamp.
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    threads = threads > 0 ? std::min(threads, cores) : cores;
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<uint64_t>(0, setup.photons, 2048),
                          [&](const tbb::blocked_range<uint64_t>& range) {
                              glsl::tPhaseTable = table.data();
                              LocalTally& local = locals.local();
                              glsl::tBins = local.rz.data();
                              glsl::tVoxels = local.grid.data();
                              glsl::tBatchStride = setup.binsPerBatch ? uint32_t(rzBins) : 0u;
                              // Batch by batch (photon i is in batch i % MC_BATCHES), so
                              // that consecutive photons add to the same copy of the bins.
                              for (uint64_t b = 0; b < MC_BATCHES; ++b)
                                  for (uint64_t i = firstOfBatch(range.begin(), b, setup);
                                       i < range.end(); i += MC_BATCHES)
                                      tracePhoton(params, derived, setup.firstPhoton + i, local);
                              progress.advance(range.size());
                          });
    });
    progress.finish();

    McResult result;
    result.setup = setup;
    result.launchWeight = params.launchWeight;
    std::vector<uint64_t> rz(rzWords, 0);
    result.absorbedGrid.assign(voxels, 0);
    for (const LocalTally& local : locals) {
        for (int b = 0; b < MC_BATCHES; ++b) result.batches[size_t(b)] += local.batches[size_t(b)];
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
