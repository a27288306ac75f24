#pragma once
/// @file
/// A job's `kernel` section: where the beam kernel comes from and how the exposure uses it.
///   {"source": "monte-carlo", "photons": 300000, "seed": 1, "use": "fitted" | "tabulated",
///    "estimator": "collision" | "track-length" | "analog" | "implicit" |
///    "implicit-track"}
///   {"source": "given", "We3D": "60 um", "De3D": "100 um", "zmax": "0 um", "efficiency": 1}
/// Either may add "plan": a kernel section of the same keys (without its own "plan") that the
/// planner plans with, while the exposure, cure and validation use the kernel above (seed 000
/// Fig. 31: a plan made for one model, printed in another).

#include <cstdint>
#include <memory>

#include "vpsim/kernel/fitted_beam.h"
#include "vpsim/transport/photon_mc.h"

namespace vpsim {
class ConfigNode;
}

namespace vpsim::kernel {

enum class KernelSource { MonteCarlo, Given };

struct KernelSpec {
    KernelSource source = KernelSource::MonteCarlo;
    uint64_t photons = 300000;  ///< Monte Carlo photons (1000 .. 1e12, 64-bit indices)
    uint32_t seed = 1;
    bool tabulated = false;  ///< expose with the Monte Carlo table instead of the Eq. 12 fit
    /// The Monte Carlo estimator of the kernel's bins (transport/photon_mc.h).
    transport::Estimator estimator = transport::Estimator::Collision;
    FittedBeam given;  ///< source == Given: the beam as written in the job
    /// The planning kernel (`kernel.plan`) when the job names one apart, else null: the
    /// planner's beam; the simulation keeps this spec's.
    std::shared_ptr<const KernelSpec> plan;
};

/// @param allowPlan whether the section may hold a `plan` kernel (not inside one)
/// @throw InputError naming the file and key
KernelSpec kernelSpecFromConfig(const ConfigNode& section, bool allowPlan = true);

}  // namespace vpsim::kernel
