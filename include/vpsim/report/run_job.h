#pragma once
/// @file
/// The main job: material -> beam kernel (cached by its inputs) -> slice -> plan -> expose ->
/// cure -> validate, with a time per stage, writing report.json, grids, the cured mesh, pictures
/// and index.html into the output directory.

#include <memory>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/report/job.h"

namespace vpsim::gpu {
class Context;
}

namespace vpsim::report {

/// Runs `job`, writing everything into `outDir` (created). Returns the report (also written as
/// outDir/report.json). `context` is the Vulkan context for the shaders, or nullptr for the CPU.
/// The photon Monte Carlo uses any context; the exposure engines use it on hardware GPUs, and on
/// a CPU driver such as lavapipe only when `exposureShadersOnCpuDevices` (there the TBB loops are
/// measured faster: bench_exposure).
/// @throw InputError, ResourceError, GpuError with one clear message
nlohmann::json runJob(const Job& job, const std::string& outDir,
                      const std::shared_ptr<gpu::Context>& context,
                      bool exposureShadersOnCpuDevices = false);

/// Directory where beam kernels are cached: $VPSIM_CACHE_DIR, else $XDG_CACHE_HOME/vpsim, else
/// ~/.cache/vpsim.
std::string kernelCacheDirectory();

}  // namespace vpsim::report
