#include "vpsim/kernel/kernel_summary.h"

#include <algorithm>

namespace vpsim::kernel {

KernelRequest kernelRequest(const std::string& materialFile, const KernelOptions& o,
                            const std::vector<std::string>& overrides) {
    KernelRequest request =
        kernelRequest(materialFile, o.power, o.w0, o.photons, o.seed, overrides);
    transport::McSetup& s = request.setup;
    if (o.thickness > 0) {  // a slab, as kernelSetup(optics, w0, thickness) bins it
        s.thickness = o.thickness;
        s.bins.zMax = std::min(s.bins.zMax, o.thickness);
    }
    s.estimator = o.estimator;
    s.nAbove = s.nBelow = o.nOutside;
    if (o.rMax > 0) s.bins.rMax = o.rMax;
    if (o.zMax > 0) s.bins.zMax = o.zMax;
    s.bins.rBins = s.bins.zBins = o.bins;
    return request;
}

nlohmann::json kernelSummaryJson(const BeamKernel& k, const transport::McSetup& s, bool fromCache) {
    return {{"We3D_um", k.fit.we3d * 1000},
            {"De3D_um", k.fit.de3d * 1000},
            {"zmax_um", k.zmax * 1000},
            {"amplitude_mW_per_mm2", k.fit.amplitude},
            {"residual", k.fit.residual},
            {"fit_energy_fraction", k.fit.energyFraction},
            {"energy_conserving_amplitude_mW_per_mm2", k.energyFit.amplitude},
            {"energy_conserving_residual", k.energyFit.residual},
            {"engine_fit", "least-squares"},
            {"estimator", transport::estimatorName(s.estimator)},
            {"W0_um", s.w0 * 1000},
            {"Dp_no_scattering_um", 1000 / s.optics.mua},
            {"no_scattering_peak_mW_per_mm2", k.beerLambert(0, 0)},
            {"from_cache", fromCache}};
}

}  // namespace vpsim::kernel
