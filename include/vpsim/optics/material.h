#pragma once
/// @file
/// Bulk optical properties of a turbid medium (what the photon Monte Carlo needs) and the loader of
/// material JSON files. Two file forms are accepted:
///
/// slurry form (optics derived by Mie theory, seed 000 Section II):
/// @code
/// {"wavelength": "405 nm",
///  "resin": {"refractive_index": 1.45, "penetration_depth": "119 um"},
///  "particles": {"refractive_index": 1.75, "radius": "2.5 um", "volume_fraction": 0.5,
///                "size_distribution": {"type": "lognormal", "sigma_g": 1.3}},   // optional
///  "phase_table_size": 4096}                                                    // optional
/// @endcode
/// plain form (bulk coefficients given directly):
/// @code
/// {"optics": {"mua": "10 /cm", "mus": "90 /cm", "g": 0.75, "phase": "hg",
/// "refractive_index": 1.0}}
/// @endcode

#include <string>
#include <vector>

namespace vpsim::optics {

/// How the scattering angle is sampled.
enum class PhaseModel { HenyeyGreenstein, Tabulated };

/// Bulk optical properties of a turbid medium as the photon Monte Carlo needs them.
struct MediumOptics {
    double mua = 0.0;              ///< absorption coefficient, 1/mm
    double mus = 0.0;              ///< scattering coefficient, 1/mm
    double g = 0.0;                ///< scattering asymmetry <cos theta>
    double refractiveIndex = 1.0;  ///< real index of the medium the photons travel in (resin)
    double wavelength = 0.0;       ///< vacuum wavelength, mm (0 when not given)
    PhaseModel phase = PhaseModel::HenyeyGreenstein;
    /// Tabulated only: inverse CDF of the polar angle, cos(theta) at u = i/(n-1), i = 0..n-1,
    /// running from +1 (u=0) to -1 (u=1); linear interpolation in u between entries.
    std::vector<float> inverseCdf;
};

/// Loads a material JSON file (slurry form or plain "optics" form, see the file comment).
/// @param path      material JSON file
/// @param overrides "key.path=value" overrides applied on top of the file (as ConfigNode::load)
/// @return the bulk optics; for the slurry form phase == Tabulated with the Mie inverse CDF
/// @throw InputError naming the file and key for any problem (unknown keys, units, ranges).
MediumOptics loadMediumOptics(const std::string& path,
                              const std::vector<std::string>& overrides = {});

}  // namespace vpsim::optics
