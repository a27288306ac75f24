#pragma once
/// @file
/// The cure models' closed forms: what a dose does to the resin (the CureLaw classes in
/// threshold_law.h and fpp_law.h use them).
///
/// Two models, both reduced to one iso-level on dose (the "critical dose") that the validation
/// uses for the cured surface:
///  - threshold (Jacobs; seed 000 Section I): resin is cured where the dose E >= Ec. With
///    Beer-Lambert attenuation E(z) = E0 exp(-z/Dp) this gives the working curve
///    Cd = Dp ln(E0/Ec).
///  - FPP, frontal photopolymerisation (seed 001 Eq. 1-2): the degree of conversion at depth z is
///        Phi(z, d) = 1 - exp(-K d exp(-mu z))            (Eq. 1)
///    where d is the surface dose, K the effective conversion rate (mm^2/mJ) and mu = 1/Dp the
///    attenuation (1/mm); d exp(-mu z) is the local dose, so locally Phi = 1 - exp(-K E).
///    Resin gels (solidifies) where Phi >= Phi_c, the gel point, which gives
///        Zf = ln(K d / ln(1/(1 - Phi_c))) / mu            (Eq. 2)
///    (Eq. 2 is the gel condition Phi(Zf, d) = Phi_c solved for Zf). This is exactly the Jacobs
///    working curve with Dp = 1/mu and Ec = ln(1/(1 - Phi_c)) / K, so both models share the
///    iso-level Ec.
/// Units: dose mJ/mm^2, length mm, K mm^2/mJ (core/units.h).

#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace vpsim {
class ConfigNode;
}

namespace vpsim::cure {

/// Jacobs working curve: cure depth Cd = Dp ln(E0/Ec) for surface dose E0.
/// @param surfaceDose E0, mJ/mm^2 (>= 0)
/// @param criticalDose Ec, mJ/mm^2 (> 0)
/// @param penetrationDepth Dp, mm (> 0)
/// @return cure depth in mm, 0 when E0 <= Ec (nothing cures)
double jacobsCureDepth(double surfaceDose, double criticalDose, double penetrationDepth);

/// Local FPP degree of conversion Phi = 1 - exp(-K E) for the local dose E (mJ/mm^2), K in
/// mm^2/mJ. Dimensionless in [0, 1).
double fppConversion(double localDose, double rateConstant);

/// Seed 001 Eq. 1: Phi(z, d) = 1 - exp(-K d exp(-mu z)) at depth z (mm) below the surface that
/// received surface dose d (mJ/mm^2), attenuation mu (1/mm).
double fppConversionAtDepth(double surfaceDose, double depth, double rateConstant,
                            double attenuation);

/// Dose (mJ/mm^2) at which the FPP conversion reaches the gel point: Ec = ln(1/(1-Phi_c)) / K.
/// @param gelPoint Phi_c in (0, 1)
double fppGelDose(double rateConstant, double gelPoint);

/// Seed 001 Eq. 2: solidified thickness Zf = ln(K d / ln(1/(1-Phi_c))) / mu (mm); 0 when the
/// surface dose is below the gel dose.
double fppCureDepth(double surfaceDose, double rateConstant, double attenuation, double gelPoint);

/// FPP rate constant K (mm^2/mJ) that makes the gel dose equal `criticalDose` (inverse of
/// fppGelDose): K = ln(1/(1-Phi_c)) / Ec.
double fppRateConstantFromCriticalDose(double criticalDose, double gelPoint);

}  // namespace vpsim::cure
