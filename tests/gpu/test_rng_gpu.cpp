#include <catch2/catch.hpp>

#include "support/gpu_test.h"
#include "vpsim/core/rng.h"
#include "vpsim/gpu/rng_stream.h"

using namespace vpsim;

// The one-source promise: the shader and the CPU compile the same rng.glsl, so every bit must
// match, raw words and floats alike (tolerance: zero).
TEST_CASE("GPU and CPU random streams are bit-identical", "[gpu][rng]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    for (uint32_t mode : {0u, 1u}) {
        auto cpu = rngStreamsCpu(2024u, 1000u, 5000u, 16u, mode);
        auto gpu = gpu::rngStreamsGpu(ctx, 2024u, 1000u, 5000u, 16u, mode);
        REQUIRE(gpu.size() == cpu.size());
        size_t mismatches = 0;
        for (size_t i = 0; i < cpu.size(); ++i) mismatches += cpu[i] != gpu[i];
        INFO("mode " << mode);
        CHECK(mismatches == 0);
    }
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}

// More than 65535 workgroups of 64: dispatch1D folds into Y, and every stream is still written.
TEST_CASE("large dispatches stay within the workgroup-count limit", "[gpu][rng]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    const uint32_t streams = 65535u * 64u + 4097u;
    auto gpu = gpu::rngStreamsGpu(ctx, 5u, 0u, streams, 1u, 0u);
    auto cpuHead = rngStreamsCpu(5u, 0u, 100u, 1u, 0u);
    auto cpuTail = rngStreamsCpu(5u, streams - 100u, 100u, 1u, 0u);
    CHECK(std::equal(cpuHead.begin(), cpuHead.end(), gpu.begin()));
    CHECK(std::equal(cpuTail.begin(), cpuTail.end(), gpu.end() - 100));
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}
