#include "vpsim/kernel/fitted_beam.h"

#include <cmath>

#include <nlohmann/json.hpp>

namespace vpsim::kernel {

nlohmann::json FittedBeam::toJson() const {
    return {{"We3D_um", radius * 1e3},
            {"De3D_um", attenuationLength * 1e3},
            {"zmax_um", depthOfMaximum * 1e3},
            {"efficiency", efficiency}};
}

FittedBeam fittedBeamOf(const BeamKernel& kernel) {
    FittedBeam beam;
    beam.radius = kernel.fit.we3d;
    beam.attenuationLength = kernel.fit.de3d;
    beam.depthOfMaximum = kernel.zmax;
    beam.efficiency =
        kernel.fit.amplitude * M_PI * kernel.fit.we3d * kernel.fit.we3d / (2.0 * kernel.power);
    return beam;
}

}  // namespace vpsim::kernel
