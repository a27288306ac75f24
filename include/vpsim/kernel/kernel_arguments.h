#pragma once
/// @file
/// The beam kernel's settings as a user gives them: `vpsim kernel`'s options and the Python
/// module's vpsim.kernel keyword arguments. Both front ends fill KernelArguments and call
/// kernelOptions(), so they accept and refuse the same values for the same reasons.

#include <cstdint>
#include <string>

#include "vpsim/kernel/kernel_summary.h"
#include "vpsim/transport/mc_arguments.h"

namespace vpsim::kernel {

/// Quantities are text with units ("10 mW", "50 um") or bare numbers in base units.
struct KernelArguments {
    std::string power = "10 mW", w0 = "50 um";
    std::string photons = "1000000";  ///< a whole number, "1e6" allowed
    uint32_t seed = 1;
    std::string thickness;   ///< slab thickness; "" = semi-infinite
    double nOutside = 1.0;   ///< refractive index above (and below) the medium
    std::string rMax, zMax;  ///< "" = chosen from W0 and mua
    uint32_t bins = 80;      ///< along r and along z, 4 .. 1000
    std::string estimator = "track-length";
};

/// @throw InputError naming the argument as `name` gives it
KernelOptions kernelOptions(const KernelArguments& arguments, const transport::ArgumentName& name);

}  // namespace vpsim::kernel
