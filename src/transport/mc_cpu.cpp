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

namespace vpsim::glsl {
#include "rng.glsl"
// The phase table of the run in progress on this thread (set by each task before tracing).
thread_local const float* tPhaseTable = nullptr;
inline float photonPhaseTable(int i) {
    return tPhaseTable[i];
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

void tracePhoton(const glsl::PhotonParams& p, uint32_t index, LocalTally& t) {
    glsl::PhotonState s;
    glsl::RngState rng;
    glsl::photonLaunch(p, index, s, rng);
    BatchTally& b = t.batches[index % MC_BATCHES];
    const uint64_t weight = p.enteringWeight;
    b.photons += 1;
    b.specular += p.launchWeight - p.enteringWeight;
    for (;;) {
        int event = glsl::photonStep(p, s, rng);
        if (event == glsl::PHOTON_EVENT_MOVED) continue;
        if (event == glsl::PHOTON_EVENT_SCATTERED) {
            b.scatterings += 1;
            continue;
        }
        switch (event) {
            case glsl::PHOTON_EVENT_REFLECTED: b.diffuse += weight; break;
            case glsl::PHOTON_EVENT_TRANSMITTED: b.transmitted += weight; break;
            case glsl::PHOTON_EVENT_ESCAPED: b.escaped += weight; break;
            default: {
                b.absorbed += weight;
                const float depth[4] = {p.depth0, p.depth1, p.depth2, p.depth3};
                for (int k = 0; k < 4; ++k)
                    if (s.pos.z < depth[k]) b.absorbedWithin[k] += weight;
                int bin = glsl::photonRzBin(p, s.pos);
                if (bin >= 0) t.rz[size_t(bin)] += weight;
                int voxel = glsl::photonGridVoxel(p, s.pos);
                if (voxel >= 0) t.grid[size_t(voxel)] += weight;
            }
        }
        return;
    }
}

}  // namespace

McResult runPhotonMcCpu(const McSetup& setup, int threads) {
    validateSetup(setup);
    const glsl::PhotonParams params = makePhotonParams(setup);
    const std::vector<float> table = makePhaseTable(setup);
    const size_t rzBins = size_t(setup.bins.rBins) * setup.bins.zBins;
    const size_t voxels = size_t(params.gridNxy) * params.gridNxy * params.gridNz;

    auto start = std::chrono::steady_clock::now();
    tbb::enumerable_thread_specific<LocalTally> locals([&] { return LocalTally(rzBins, voxels); });
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
                              for (uint64_t i = range.begin(); i != range.end(); ++i)
                                  tracePhoton(params, uint32_t(i), local);
                              progress.advance(range.size());
                          });
    });
    progress.finish();

    McResult result;
    result.setup = setup;
    result.launchWeight = params.launchWeight;
    result.absorbedRZ.assign(rzBins, 0);
    result.absorbedGrid.assign(voxels, 0);
    for (const LocalTally& local : locals) {
        for (int b = 0; b < MC_BATCHES; ++b) result.batches[size_t(b)] += local.batches[size_t(b)];
        for (size_t i = 0; i < rzBins; ++i) result.absorbedRZ[i] += local.rz[i];
        for (size_t i = 0; i < voxels; ++i) result.absorbedGrid[i] += local.grid[i];
    }
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.backend = "cpu (" + std::to_string(threads) + " threads)";
    return result;
}

}  // namespace vpsim::transport
