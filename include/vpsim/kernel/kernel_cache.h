#pragma once
/// @file
/// Beam kernels from the photon Monte Carlo, cached on disk under the run's cache directory by a
/// hash of everything they depend on (the material file's text, power, beam, photons, seed,
/// bins, boundaries), so `vpsim run` and `vpsim kernel` reuse each other's kernels.

#include <string>

#include "vpsim/core/run_context.h"
#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/transport/photon_mc.h"

namespace vpsim::kernel {

/// One kernel to compute: the Monte Carlo setup (from kernelSetup(), possibly adjusted) of the
/// material in `materialFile`, for incident power `power` (mW).
struct KernelRequest {
    std::string materialFile;
    transport::McSetup setup;
    double power = 10.0;
};

/// The request of a material file's kernel with the default bins (kernelSetup()).
/// @throw InputError naming the file when it cannot be read or does not absorb (mua = 0:
///        Eq. 11 divides by mua), before any photon is traced
KernelRequest kernelRequest(const std::string& materialFile, double power, double w0,
                            uint64_t photons, uint32_t seed,
                            const std::vector<std::string>& overrides = {});

/// Loads the kernel from `context.cacheDirectory` or runs the Monte Carlo (on context.gpu when
/// set) and stores it there. `fromCache` tells which; `monteCarlo`, when given, receives the
/// Monte Carlo result of a fresh run. An unreadable cache entry is recomputed.
BeamKernel cachedKernel(const KernelRequest& request, const RunContext& context, bool& fromCache,
                        transport::McResult* monteCarlo = nullptr);

/// The default cache directory for a user: $VPSIM_CACHE_DIR, else $XDG_CACHE_HOME/vpsim, else
/// ~/.cache/vpsim. Read by the CLI (the library itself reads no environment).
std::string defaultKernelCacheDirectory(const char* vpsimCacheDir, const char* xdgCacheHome,
                                        const char* home);

}  // namespace vpsim::kernel
