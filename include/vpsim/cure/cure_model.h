#pragma once
/// @file
/// Cure models: what a dose does to the resin.
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

/// Which law converts dose into conversion.
enum class CureModelKind { Threshold, Fpp };

/// A resin's cure law with its parameters (plain value type).
/// The iso-level criticalDose() is the dose of the cured surface for both kinds.
class CureModel {
public:
    /// Jacobs threshold model. @param criticalDose Ec, mJ/mm^2 (> 0)
    /// @param penetrationDepth Dp, mm (> 0), or 0 when attenuation is left to the exposure
    ///        kernel (e.g. a Monte Carlo beam kernel in a slurry)
    /// @throw InputError on a non-positive or non-finite parameter
    static CureModel threshold(double criticalDose, double penetrationDepth = 0.0);
    /// FPP model. @param rateConstant K, mm^2/mJ (> 0) @param gelPoint Phi_c in (0, 1)
    /// @param penetrationDepth Dp = 1/mu, mm (> 0), or 0 when not known
    /// @throw InputError on a parameter out of range
    static CureModel fpp(double rateConstant, double gelPoint, double penetrationDepth = 0.0);

    CureModelKind kind() const { return mKind; }
    /// "threshold" or "fpp".
    std::string kindName() const;
    /// Iso-level on dose of the cured surface, mJ/mm^2: Ec, or the FPP gel dose.
    double criticalDose() const { return mCriticalDose; }
    /// K, mm^2/mJ (FPP only; 0 for threshold).
    double rateConstant() const { return mRateConstant; }
    /// Phi_c (FPP only; 0 for threshold).
    double gelPoint() const { return mGelPoint; }
    /// Dp, mm; 0 when not given.
    double penetrationDepth() const { return mPenetrationDepth; }
    bool hasPenetrationDepth() const { return mPenetrationDepth > 0.0; }

    /// Degree of conversion for a local dose (mJ/mm^2): FPP 1 - exp(-K E); threshold is a step,
    /// 1 at and above Ec and 0 below (the threshold model knows nothing in between).
    double conversion(double dose) const;
    /// Cured (gelled) at this local dose: dose >= criticalDose().
    bool isCured(double dose) const { return dose >= mCriticalDose; }
    /// Cure depth (mm) for a surface dose under Beer-Lambert attenuation with Dp: the working
    /// curve Dp ln(E0/Ec) (identical to Eq. 2 for FPP).
    /// @throw InputError when the model has no penetration depth
    double cureDepth(double surfaceDose) const;

    /// Parameters in base units: {"model", "critical_dose", "penetration_depth"?, "K"?,
    /// "gel_point"?}; loadable again by cureModelFromJson.
    nlohmann::json toJson() const;

private:
    CureModel() = default;
    CureModelKind mKind = CureModelKind::Threshold;
    double mCriticalDose = 0.0;
    double mRateConstant = 0.0;
    double mGelPoint = 0.0;
    double mPenetrationDepth = 0.0;
};

/// Reads a cure section of a material/resin config, e.g.
/// @code
/// {"model": "fpp", "K": "0.00528 cm^2/mJ", "gel_point": 0.276, "penetration_depth": "0.366 mm"}
/// {"model": "fpp", "critical_dose": "61 mJ/cm^2", "gel_point": 0.276, "attenuation": "27 /cm"}
/// {"model": "threshold", "critical_dose": "61 mJ/cm^2", "penetration_depth": "366 um"}
/// @endcode
/// FPP takes exactly one of K or critical_dose (then K = ln(1/(1-Phi_c))/Ec); either model takes
/// at most one of penetration_depth or attenuation (= 1/Dp), both optional. Keys of the section
/// are read and checked here: an unknown key inside it is an error; the parent's own
/// checkUnknownKeys() sees the section as read.
/// @param parent node holding the section @param key the section's key (e.g. "cure")
/// @throw InputError naming the file and the key path ("cure.K") and the reason
CureModel cureModelFromConfig(const ConfigNode& parent, const std::string& key);

/// Same for a JSON object given directly (file names the source in messages, keyPrefix is
/// prepended to key paths in messages, e.g. "cure").
/// @throw InputError as cureModelFromConfig
CureModel cureModelFromJson(const nlohmann::json& section, const std::string& file = "",
                            const std::string& keyPrefix = "");

}  // namespace vpsim::cure
