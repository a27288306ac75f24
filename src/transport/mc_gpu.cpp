// Vulkan path of the photon Monte Carlo (shaders/photon_mc.comp), and the backend choice.

#include <algorithm>
#include <chrono>

#include "photon_params.h"
#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/core/progress.h"
#include "vpsim/gpu/context.h"
#include "vpsim/shaders/photon_mc_spv.h"
#include "vpsim/transport/beam_convolution.h"

namespace vpsim::transport {

namespace {

/// Photons per submission: bounds each submission's run time (progress, no driver timeouts).
constexpr uint64_t PHOTONS_PER_SUBMIT = 1u << 20;
/// Each invocation traces about this many photons: enough to even out photon lengths, few
/// enough that there are many invocations to fill the device.
constexpr uint64_t PHOTONS_PER_INVOCATION = 32;
constexpr uint64_t MAX_INVOCATIONS = 1u << 18;
constexpr uint32_t LOCAL_SIZE = 64;  // photon_mc.comp local_size_x
static_assert(MC_CONTROL_BATCHES % LOCAL_SIZE == 0 && MAX_INVOCATIONS % MC_CONTROL_BATCHES == 0,
              "invocation counts are multiples of the control batches");

uint32_t invocationsFor(uint64_t photons) {
    // A multiple of MC_CONTROL_BATCHES (so of LOCAL_SIZE and MC_BATCHES too): all photons of an
    // invocation are in one batch and one control batch.
    const uint64_t n =
        std::clamp<uint64_t>(photons / PHOTONS_PER_INVOCATION, MC_CONTROL_BATCHES, MAX_INVOCATIONS);
    return uint32_t((n + MC_CONTROL_BATCHES - 1) / MC_CONTROL_BATCHES * MC_CONTROL_BATCHES);
}

}  // namespace

McResult runPhotonMcGpu(const McSetup& setup, const std::shared_ptr<gpu::Context>& context) {
    validateSetup(setup);
    if (!context) throw GpuError("photon Monte Carlo: no Vulkan context");
    if (convolvesBeam(setup))
        return convolveBeam(runPhotonMcGpu(pencilSetup(setup), context), setup);
    const auto& info = context->info();
    if (!info.int64 || !info.int64Atomics)
        throw GpuError(
            "photon Monte Carlo needs shaderInt64 and shaderBufferInt64Atomics for its exact "
            "integer tallies; device '" +
            info.name + "' lacks them (use --backend cpu)");

    glsl::PhotonParams params = makePhotonParams(setup);
    std::vector<float> table = makePhaseTable(setup);
    const uint64_t rzBins = uint64_t(setup.bins.rBins) * setup.bins.zBins;
    const uint64_t voxels = uint64_t(params.gridNxy) * params.gridNxy * params.gridNz;
    const uint64_t rzWords = setup.binsPerBatch ? rzBins * MC_BATCHES : rzBins;
    const uint64_t tallyWords = glsl::PHOTON_BIN_OFFSET + rzWords;
    for (uint64_t bytes : {tallyWords * 8, voxels * 8})
        if (bytes > info.maxStorageBufferRange)
            throw ResourceError("photon Monte Carlo tally of " + formatBytes(double(bytes)) +
                                " exceeds the device's storage-buffer limit of " +
                                formatBytes(double(info.maxStorageBufferRange)) +
                                ": use fewer bins");

    auto start = std::chrono::steady_clock::now();
    const uint32_t capacity = uint32_t(std::max<size_t>(table.size(), 1));
    gpu::Kernel kernel(
        context, photon_mc_spv, sizeof photon_mc_spv, 4, sizeof(glsl::PhotonParams),
        {gpu::SpecConstant{0, capacity}, gpu::SpecConstant{1, params.estimator & 255u}},
        LOCAL_SIZE);
    gpu::Buffer tallies(context, tallyWords * 8);
    tallies.fill(0);
    gpu::Buffer tableBuffer(context, std::max<uint64_t>(table.size(), 1) * sizeof(float));
    if (!table.empty()) tableBuffer.upload(table);
    gpu::Buffer grid(context, std::max<uint64_t>(voxels, 1) * 8);
    grid.fill(0);
    // Photon states of invocations that ran out of their per-dispatch work budget.
    gpu::Buffer resume(context, (glsl::PHOTON_RESUME_HEADER +
                                 uint64_t(MAX_INVOCATIONS) * glsl::PHOTON_RESUME_SLOT) *
                                    sizeof(uint32_t));
    resume.fill(0);

    Progress progress("photon Monte Carlo (GPU)", setup.photons);
    for (uint64_t first = 0; first < setup.photons; first += PHOTONS_PER_SUBMIT) {
        uint64_t count = std::min(PHOTONS_PER_SUBMIT, setup.photons - first);
        const uint64_t index = setup.firstPhoton + first;
        params.photonStart = uint32_t(index);
        params.photonStartHi = uint32_t(index >> 32);
        params.photonCount = uint32_t(count);
        params.invocationStride = invocationsFor(count);
        // Dispatch until no invocation is left suspended (one dispatch in ordinary media).
        const uint32_t flags = params.estimator & ~glsl::PHOTON_FLAG_RESUME;
        for (uint32_t suspended = 1, pass = 0; suspended > 0; ++pass) {
            params.estimator = flags | (pass > 0 ? glsl::PHOTON_FLAG_RESUME : 0u);
            context->submit([&](gpu::Recorder& r) {
                r.dispatch1D(kernel, {&tallies, &tableBuffer, &grid, &resume}, &params,
                             params.invocationStride);
            });
            resume.download(&suspended, sizeof suspended);
            const uint32_t zero = 0;
            if (suspended > 0) resume.upload(&zero, sizeof zero);
        }
        params.estimator = flags;
        progress.advance(count);
    }
    progress.finish();

    McResult result;
    result.setup = setup;
    result.launchWeight = params.launchWeight;
    std::vector<uint64_t> words = tallies.download<uint64_t>(tallyWords);
    for (int b = 0; b < MC_BATCHES; ++b) {
        const uint64_t* w = words.data() + size_t(b) * glsl::PHOTON_TALLY_STRIDE;
        BatchTally& t = result.batches[size_t(b)];
        t.photons = photonsInBatch(setup.firstPhoton, setup.photons, b);
        t.specular = w[glsl::PHOTON_TALLY_SPECULAR];
        t.diffuse = w[glsl::PHOTON_TALLY_DIFFUSE];
        t.transmitted = w[glsl::PHOTON_TALLY_TRANSMITTED];
        t.absorbed = w[glsl::PHOTON_TALLY_ABSORBED];
        t.escaped = w[glsl::PHOTON_TALLY_ESCAPED];
        t.scatterings = w[glsl::PHOTON_TALLY_SCATTERINGS];
        t.interactions = w[glsl::PHOTON_TALLY_INTERACTIONS];
        t.rouletteGain = w[glsl::PHOTON_TALLY_ROULETTE_GAIN];
        t.rouletteLoss = w[glsl::PHOTON_TALLY_ROULETTE_LOSS];
        for (size_t k = 0; k < 4; ++k) t.absorbedWithin[k] = w[glsl::PHOTON_TALLY_WITHIN + k];
    }
    if (result.controlled()) {
        result.controlBatches.resize(MC_CONTROL_BATCHES);
        for (size_t j = 0; j < size_t(MC_CONTROL_BATCHES); ++j) {
            const uint64_t* w =
                words.data() + glsl::PHOTON_CONTROL_OFFSET + j * glsl::PHOTON_CONTROL_STRIDE;
            ControlTally& c = result.controlBatches[j];
            c.diffuse = w[0];
            c.transmitted = w[1];
            for (size_t k = 0; k < 4; ++k) c.absorbedWithin[k] = w[2 + k];
            for (size_t i = 0; i < c.controls.size(); ++i) c.controls[i] = int64_t(w[6 + i]);
        }
    }
    setBins(result, std::vector<uint64_t>(words.begin() + glsl::PHOTON_BIN_OFFSET, words.end()),
            params);
    if (voxels > 0) result.absorbedGrid = grid.download<uint64_t>(voxels);
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.backend = info.name;
    return result;
}

McResult runPhotonMc(const McSetup& setup, const std::shared_ptr<gpu::Context>& context) {
    if (context && !(context->info().int64 && context->info().int64Atomics)) {
        logWarn("photon Monte Carlo: device '" + context->info().name +
                "' lacks 64-bit buffer atomics; running on the CPU");
        return runPhotonMcCpu(setup);
    }
    return context ? runPhotonMcGpu(setup, context) : runPhotonMcCpu(setup);
}

}  // namespace vpsim::transport
