#pragma once
/// @file
/// Material JSON files (see material.h for the two forms) read into their specification without
/// computing anything yet, so the CLI can report the Mie inputs of a slurry.
///
/// Slurry keys (units may be given as strings, bare numbers are base units mm):
///   wavelength                         vacuum wavelength (length)
///   resin.refractive_index             real index of the resin (> 0)
///   resin.penetration_depth            Dp0 of the pure resin (length > 0), seed 000 Eq. 10
///   resin.absorption                   "pure_resin" (default, as seed 000: mua = 1/Dp0) or
///                                      "resin_fraction" (mua = (1 - Phi)/Dp0)
///   particles.refractive_index         number or "n-ki" string (k >= 0, see mie.h)
///   particles.radius                   radius, or geometric mean radius for lognormal (length > 0)
///   particles.volume_fraction          solid fraction Phi in (0, 0.74)
///   particles.size_distribution        optional {"type": "monodisperse" | "lognormal",
///                                      "sigma_g": >= 1, "points": quadrature points (96)}
///   phase_table_size                   optional inverse-CDF entries (4096)
/// Plain keys: optics.mua, optics.mus (attenuation, e.g. "10 /cm"), optics.g in (-1, 1),
///   optics.phase ("hg"), optics.refractive_index (1.0), optics.wavelength (optional length).
/// Both forms may carry "name" and "description" strings.

#include <string>
#include <vector>

#include "vpsim/optics/material.h"
#include "vpsim/optics/slurry.h"

namespace vpsim::optics {

/// A parsed material file.
struct MaterialDefinition {
    std::string file;
    std::string name;
    bool isSlurry = false;
    SlurrySpec slurry;    ///< valid when isSlurry
    MediumOptics optics;  ///< valid when !isSlurry (bulk coefficients given directly)
};

/// Reads and checks a material file. @throw InputError naming the file and key for malformed JSON,
/// unknown keys, wrong units and impossible values.
MaterialDefinition loadMaterialDefinition(const std::string& path,
                                          const std::vector<std::string>& overrides = {});

/// Slurry optics of a slurry definition. @throw InputError (naming the file) when the Mie
/// computation refuses the inputs, or when the definition is not a slurry.
SlurryOptics computeSlurryOptics(const MaterialDefinition& material);

}  // namespace vpsim::optics
