#pragma once
/// @file
/// The fitted beam kernel of seed 000 Eq. 12 as the exposure engine and the planners use it: a
/// Gaussian of 1/e^2 radius We3D in x and y times an exponential of 1/e depth De3D, with the
/// depth of the sub-surface maximum and the fraction of the beam's energy it carries. One type
/// for a Monte Carlo fit, a kernel given in a job, and an ideal DLP projector blur.

#include <nlohmann/json_fwd.hpp>

#include "vpsim/kernel/beam_kernel.h"

namespace vpsim::kernel {

struct FittedBeam {
    double radius = 0.05;            ///< mm, 1/e^2 intensity radius (We3D)
    double attenuationLength = 0.1;  ///< mm, 1/e depth of the exposure (De3D)
    double depthOfMaximum = 0.0;     ///< mm, depth of the sub-surface maximum (zmax)
    /// Surface exposure per delivered energy relative to a lossless Gaussian: the fitted
    /// amplitude Ie3D(0,0) pi We3D^2 / (2 P) of a Monte Carlo kernel (reflection losses and
    /// scattering lower it), 1 for an ideal beam.
    double efficiency = 1.0;

    /// {"We3D_um", "De3D_um", "zmax_um", "efficiency"}
    nlohmann::json toJson() const;
};

/// The fitted beam of a Monte Carlo kernel (its Eq. 12 fit and zmax).
FittedBeam fittedBeamOf(const BeamKernel& kernel);

}  // namespace vpsim::kernel
