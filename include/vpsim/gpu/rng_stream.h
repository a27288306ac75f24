#pragma once
/// @file
/// GPU side of the RNG identity check: runs shaders/rng_stream.comp.

#include <cstdint>
#include <memory>
#include <vector>

#include "vpsim/gpu/context.h"

namespace vpsim::gpu {

/// GPU counterpart of vpsim::rngStreamsCpu (same arguments, same output layout).
/// @param gpuMs if not null, receives the GPU time in milliseconds
/// @throw GpuError, ResourceError (output larger than one storage buffer)
std::vector<uint32_t> rngStreamsGpu(const std::shared_ptr<Context>& context, uint32_t seed,
                                    uint32_t firstStream, uint32_t streamCount,
                                    uint32_t valuesPerStream, uint32_t mode,
                                    double* gpuMs = nullptr);

}  // namespace vpsim::gpu
