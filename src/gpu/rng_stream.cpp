#include "vpsim/gpu/rng_stream.h"

#include "vpsim/core/error.h"
#include "vpsim/core/glsl_shim.h"
#include "vpsim/shaders/rng_stream_spv.h"

namespace vpsim::glsl {
#include "shared_structs.glsl"
}  // namespace vpsim::glsl

namespace vpsim::gpu {

std::vector<uint32_t> rngStreamsGpu(const std::shared_ptr<Context>& context, uint32_t seed,
                                    uint32_t firstStream, uint32_t streamCount,
                                    uint32_t valuesPerStream, uint32_t mode, double* gpuMs) {
    uint64_t count = uint64_t(streamCount) * valuesPerStream;
    if (count == 0) return {};
    if (count > UINT32_MAX)
        throw ResourceError("RNG output of " + std::to_string(count) + " words is too large");
    Buffer output(context, count * sizeof(uint32_t));
    Kernel kernel(context, rng_stream_spv, sizeof rng_stream_spv, 1, sizeof(glsl::RngStreamParams),
                  {}, 64);
    glsl::RngStreamParams params{};
    params.seed = seed;
    params.firstStream = firstStream;
    params.streamCount = streamCount;
    params.valuesPerStream = valuesPerStream;
    params.mode = mode;
    double ms = context->submit(
        [&](Recorder& r) { r.dispatch1D(kernel, {&output}, &params, streamCount); });
    if (gpuMs) *gpuMs = ms;
    return output.download<uint32_t>(count);
}

}  // namespace vpsim::gpu
