#pragma once
/// @file
/// What a run needs from its surroundings, set by the caller (the CLI, a test, a benchmark) and
/// passed down: where the physics runs and where caches live. The library reads no environment
/// variables; the CLI turns VPSIM_BACKEND, VPSIM_DEVICE, VPSIM_CACHE_DIR, ... into this.

#include <memory>
#include <string>

namespace vpsim::gpu {
class Context;
}

namespace vpsim {

struct RunContext {
    /// The Vulkan context for compute shaders, or nullptr for the CPU paths.
    std::shared_ptr<gpu::Context> gpu;
    /// Run the compute shaders (exposure, photon Monte Carlo) on a CPU driver (lavapipe) too; by
    /// default they run only on hardware GPUs, since the TBB paths built from the same source are
    /// faster on a CPU (bench_exposure; bench_photon_mc: 1.5-2x per core). gpu::shaderContext
    /// applies this.
    bool shadersOnCpuDevices = false;
    /// Directory of the beam-kernel cache; "" disables caching.
    std::string cacheDirectory;
};

}  // namespace vpsim
