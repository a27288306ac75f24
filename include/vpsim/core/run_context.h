#pragma once
/// @file
/// What a run needs from its surroundings, set by the caller (the CLI, a test, a benchmark) and
/// passed down: where the physics runs, where caches live and how much memory a run may take. The
/// library reads no environment variables; the CLI turns VPSIM_BACKEND, VPSIM_DEVICE,
/// VPSIM_CACHE_DIR, VPSIM_MEMORY_LIMIT, ... into this.

#include <cstdint>
#include <memory>
#include <string>

namespace vpsim::gpu {
class Context;
}
namespace vpsim::cluster {
class Communicator;
}

namespace vpsim {

struct RunContext {
    /// The Vulkan context for compute shaders, or nullptr for the CPU paths. The exposure shaders
    /// run on it whatever the device (on lavapipe within 1.5x of the TBB loops built from the same
    /// source: bench_pipeline --engines).
    std::shared_ptr<gpu::Context> gpu;
    /// Run the photon Monte Carlo shader on a CPU driver (lavapipe) too; by default it runs only on
    /// hardware GPUs, since its TBB path built from the same source is faster on a CPU
    /// (bench_photon_mc: 1.5-2x per core) and the kernel it makes is cached.
    /// gpu::monteCarloContext applies this.
    bool monteCarloOnCpuDevices = false;
    /// Directory of the beam-kernel cache; "" disables caching.
    std::string cacheDirectory;
    /// Bytes a run may hold in its largest structures (the job estimate's peak, checkMemory);
    /// 0: the default, half the physical memory, at most 16 GiB (core/resources.h memoryBudget).
    /// The CLI sets it from VPSIM_MEMORY_LIMIT.
    uint64_t memoryLimit = 0;
    /// The ranks that share the run's work (the beam kernel's photons) when started by
    /// mpirun/srun; nullptr or one rank: this process does everything (cluster/communicator.h).
    std::shared_ptr<cluster::Communicator> cluster = nullptr;
};

}  // namespace vpsim
