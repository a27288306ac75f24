#pragma once
/// @file
/// The photon Monte Carlo's settings as a user gives them: `vpsim mc`'s options and the Python
/// module's vpsim.mc keyword arguments. Both front ends fill McArguments and call mcSetup(), so
/// they accept and refuse the same values for the same reasons.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "vpsim/core/run_context.h"
#include "vpsim/transport/photon_mc.h"

namespace vpsim::transport {

/// Lengths are text with units ("50 um") or bare numbers in mm.
struct McArguments {
    std::string photons = "100000";  ///< a whole number, "1e6" allowed
    uint32_t seed = 1;
    std::string thickness;        ///< slab thickness; "" = semi-infinite
    double nOutside = 1.0;        ///< refractive index above (and below) the medium
    std::string beam = "pencil";  ///< pencil | gaussian
    std::string w0 = "50 um";
    std::vector<std::string> depths;  ///< for absorbed_within
    std::string rMax = "0.5 mm", zMax = "0.5 mm";
    uint32_t bins = 100;  ///< along r and along z
    std::string voxel;    ///< edge of a Cartesian absorption grid; "" = none
    std::string estimator = estimatorName(McSetup{}.estimator);
    double roulette = DEFAULT_ROULETTE_THRESHOLD;
    bool directBeam = false;
    bool controlVariates = true;
};

/// How a front end names an argument ("r_max") in its messages ("--r-max").
using ArgumentName = std::function<std::string(const std::string& key)>;

/// A photon count written as an integer or in exponent form ("1e6"), from 1 to MAX_PHOTONS.
/// @throw InputError naming `key`
uint64_t parsePhotonCount(const std::string& text, const std::string& key);

/// The run of `arguments` in a medium of `optics`; the Cartesian grid is checked against the
/// context's memory budget before it is sized.
/// @throw InputError naming the argument, ResourceError for a grid beyond the budget
McSetup mcSetup(const McArguments& arguments, const optics::MediumOptics& optics,
                const ArgumentName& name, const RunContext& context);

}  // namespace vpsim::transport
