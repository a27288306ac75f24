#pragma once
/// @file
/// The figures of `vpsim mie --json` (and the Python module's vpsim.mie / vpsim.material) as one
/// JSON document each, so the CLI and the bindings report the same keys.

#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/optics/mie.h"
#include "vpsim/optics/slurry.h"

namespace vpsim::optics {

/// {"x", "m": [re, im], "qext", "qsca", "qabs", "qback", "g", "terms"} of one sphere, and for
/// `anglesDeg` (degrees, in [0, 180]) "angles_deg", "s1" and "s2" as lists of [re, im].
/// @throw InputError for an angle outside [0, 180] or what checkMieInput refuses
nlohmann::json mieSphereJson(Complex m, double x, const std::vector<double>& anglesDeg = {});

/// A slurry's optics: the nominal sphere's figures as mieSphereJson (efficiencies are the
/// ensemble's), "scattering_mean_free_path_um", "transport_mean_free_path_um", "mus_per_mm",
/// "mua_per_mm", "phase_table_size", "phase_table_mean_cosine", and for `cdfAnglesDeg` (degrees)
/// "cdf_angles_deg" and "cdf".
nlohmann::json slurryOpticsJson(const SlurryOptics& slurry,
                                const std::vector<double>& anglesDeg = {},
                                const std::vector<double>& cdfAnglesDeg = {});

/// @throw InputError naming `option` for an angle outside [0, 180] degrees
void checkAngles(const std::vector<double>& anglesDeg, const std::string& option);

}  // namespace vpsim::optics
