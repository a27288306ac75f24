#pragma once
/// @file
/// The request and the figures of `vpsim kernel` (and the Python module's vpsim.kernel), shared
/// so both run the same Monte Carlo and report the same keys.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/kernel/kernel_cache.h"

namespace vpsim::kernel {

/// What `vpsim kernel` lets a user choose beyond kernelRequest()'s defaults.
struct KernelOptions {
    double power = 10.0;  ///< mW
    double w0 = 0.05;     ///< mm
    uint64_t photons = 1000000;
    uint32_t seed = 1;
    double thickness = 0.0;  ///< mm; 0 = semi-infinite
    double nOutside = 1.0;   ///< refractive index above (and below) the medium
    double rMax = 0.0;       ///< mm; 0 = kernelSetup's (4 W0)
    double zMax = 0.0;       ///< mm; 0 = kernelSetup's (3/mua, at most the slab)
    uint32_t bins = 80;      ///< along r and along z
    transport::Estimator estimator = transport::Estimator::Track;
};

/// The request of a material file's kernel with `options` applied.
/// @throw InputError as kernelRequest()
KernelRequest kernelRequest(const std::string& materialFile, const KernelOptions& options,
                            const std::vector<std::string>& overrides = {});

/// `vpsim kernel --json`'s figures: We3D_um, De3D_um, zmax_um, amplitude_mW_per_mm2, residual,
/// fit_energy_fraction, energy_conserving_*, engine_fit, estimator, W0_um,
/// Dp_no_scattering_um, no_scattering_peak_mW_per_mm2, from_cache.
nlohmann::json kernelSummaryJson(const BeamKernel& kernel, const transport::McSetup& setup,
                                 bool fromCache);

}  // namespace vpsim::kernel
