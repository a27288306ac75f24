#pragma once
/// @file
/// Bulk optics of a ceramic slurry (spherical particles in a resin) from Mie theory, following
/// seed 000 Section II: x = 2 pi r n_resin / lambda0, m = n_particle / n_resin, Qs (Eq. 9),
/// scattering mean free path lambda_s = 4 r / (3 Phi Qs) (Eq. 8), phase PDF (Eq. 5), and
/// absorption by the resin with its penetration depth (Eq. 10).
///
/// Reading of the seed (Eq. 4): its x = 2 pi R / lambda uses the wavelength in the medium the
/// light travels in, lambda0 / n_resin, so x = 2 pi R n_resin / lambda0 (x = 56.24 for the seed).
///
/// Reading of the seed (Eq. 9): the printed formula 2/x^2 sum (2j+1) Re(a_j + b_j) is the
/// extinction efficiency; it equals the scattering efficiency for the seed's non-absorbing
/// alumina. vpsim uses Qsca (2/x^2 sum (2j+1)(|a_j|^2+|b_j|^2)) for scattering and puts any
/// particle absorption Qabs = Qext - Qsca into mua.
///
/// Reading of the seed (Eq. 10): the seed absorbs with the pure-resin penetration depth
/// Dp0 = 119 um directly (Pa(l) = exp(-l/Dp0)), not scaled by the resin fraction (1 - Phi).
/// vpsim follows it: mua = 1/Dp0 (+ particle absorption). The option
/// absorptionScaledByResinFraction gives mua = (1 - Phi)/Dp0 instead.

#include <vector>

#include "vpsim/optics/material.h"
#include "vpsim/optics/mie.h"
#include "vpsim/optics/phase_table.h"

namespace vpsim::optics {

/// Particle size distribution.
struct SizeDistribution {
    enum class Kind { Monodisperse, LogNormal };
    Kind kind = Kind::Monodisperse;
    /// LogNormal: geometric standard deviation sigma_g (> 1) of the number distribution of radii,
    /// whose geometric mean (median) radius is SlurrySpec::radius.
    double sigmaG = 1.0;
    /// LogNormal: trapezoid points in ln r over +-6 ln sigma_g (the r^3-weighted tail that sets
    /// the number density needs the wide range).
    int points = 96;
};

/// The inputs of a slurry material file, in base units.
struct SlurrySpec {
    double wavelength = 0.0;             ///< vacuum wavelength, mm
    double resinIndex = 1.0;             ///< real refractive index of the resin
    double resinPenetrationDepth = 0.0;  ///< Dp0 of the pure resin, mm
    Complex particleIndex{1.0, 0.0};     ///< particle index n - ik (k >= 0)
    double radius = 0.0;                 ///< particle radius (LogNormal: geometric mean), mm
    double volumeFraction = 0.0;         ///< solid volume fraction Phi, (0, 0.74)
    SizeDistribution size;
    int phaseTableSize = DEFAULT_PHASE_TABLE_SIZE;  ///< inverse-CDF entries
    bool absorptionScaledByResinFraction = false;   ///< mua = (1-Phi)/Dp0 instead of 1/Dp0
};

/// Derived slurry optics.
struct SlurryOptics {
    double x = 0.0;                       ///< size parameter at SlurrySpec::radius
    Complex m{1.0, 0.0};                  ///< relative index n_particle / n_resin
    MieEfficiencies efficiencies;         ///< at radius (monodisperse) or <C>/<pi r^2> averages
    double scatteringCrossSection = 0.0;  ///< mean Csca per particle, mm^2
    double scatteringMeanFreePath = 0.0;  ///< lambda_s = 1/mus, mm (Eq. 8 when monodisperse)
    double transportMeanFreePath = 0.0;   ///< lambda_s / (1 - g), mm
    PhaseTable phase;                     ///< Eq. 5 phase function of the ensemble
    MediumOptics medium;                  ///< what the Monte Carlo needs (phase = Tabulated)
};

/// @throw InputError naming the field for impossible inputs (radius <= 0, Phi outside (0, 0.74),
/// indices <= 0, wavelength or Dp0 <= 0, sigma_g < 1, table size < 2, too-large size parameter).
void validateSlurrySpec(const SlurrySpec& spec);

/// Computes the slurry optics and its phase table. @throw InputError via validateSlurrySpec
SlurryOptics computeSlurryOptics(const SlurrySpec& spec);

}  // namespace vpsim::optics
