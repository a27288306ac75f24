#pragma once
/// @file
/// The cure-law interface: the only place that decides whether resin at a local dose is cured,
/// and what its degree of conversion is where the law has one. Validation, feature probes,
/// pictures and the cured-surface mesher all ask a CureLaw.
///
/// A law maps the local dose E (mJ/mm^2) to a state and must be monotone: more light never
/// un-cures resin. So every law has one flip point, criticalDose(), and isCured(E) is
/// E >= criticalDose(); the cured surface is the iso-surface of the exposure at that dose.
///
/// Laws are created by name ("model" in a cure section) through a CureLawRegistry filled by
/// registerBuiltins(): a new law is a new file pair plus one registration line. Built in:
/// "threshold" (Jacobs; threshold_law.h) and "fpp" (seed 001's frontal photopolymerisation;
/// fpp_law.h).

#include <cstddef>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/core/registry.h"

namespace vpsim::cure {

/// Conversion kinetics Phi(E) = 1 - exp(-K E) with gelation at Phi_c (seed 001 Eq. 1-2), for
/// planners that optimise the degree of conversion.
struct ConversionKinetics {
    double rateConstant = 0;  ///< K, mm^2/mJ
    double gelPoint = 0;      ///< Phi_c
};

class CureLaw {
public:
    virtual ~CureLaw() = default;
    /// The registered name ("threshold", "fpp").
    virtual std::string name() const = 0;
    /// The dose at which the resin cures (gels), mJ/mm^2: the iso-level of the cured surface.
    virtual double criticalDose() const = 0;
    /// Cured (gelled) at this local dose (mJ/mm^2). NaN is not cured.
    bool isCured(double dose) const { return dose >= criticalDose(); }
    /// The smallest float f with double(f) >= criticalDose(): for a float dose d, d >= f is
    /// exactly isCured(d), compared in float (vectorisable loops over slices).
    float curedFloatThreshold() const { return floatAtLeast(criticalDose()); }
    /// The smallest float f with double(f) >= value.
    static float floatAtLeast(double value);
    /// Degree of conversion at a local dose (dimensionless, [0, 1]); a law without a conversion
    /// model answers 0 or 1 (hasConversion() false).
    virtual double conversion(double dose) const = 0;
    virtual bool hasConversion() const = 0;
    /// The law's first-order kinetics when it has them (FPP), else nullopt.
    virtual std::optional<ConversionKinetics> conversionKinetics() const { return std::nullopt; }
    /// conversion() over an array (overridden where a vectorised kernel exists).
    virtual void conversionRange(const float* dose, size_t count, float* conversion) const;
    /// Dp (mm) of the resin, 0 when the law was given none (e.g. a slurry whose attenuation
    /// comes from the Monte Carlo kernel).
    virtual double penetrationDepth() const = 0;
    bool hasPenetrationDepth() const { return penetrationDepth() > 0; }
    /// Jacobs working curve Dp ln(E0/Ec) under Beer-Lambert attenuation (identical to seed 001
    /// Eq. 2 for FPP), mm. @throw InputError when the law has no penetration depth
    double cureDepth(double surfaceDose) const;
    /// Parameters in base units, {"model": name(), ...}; read back by cureLawFromJson.
    virtual nlohmann::json toJson() const = 0;
};

using CureLawRegistry = Registry<CureLaw>;

/// Creates the law of a cure section, e.g. {"model": "fpp", "K": "0.0053 cm^2/mJ",
/// "gel_point": 0.276, "penetration_depth": "366 um"}. The law's factory reads its own keys;
/// an unknown key inside the section is an error; the parent sees the section as read.
/// @throw InputError naming the file and the key path ("cure.K") and the reason
std::unique_ptr<CureLaw> cureLawFromConfig(const CureLawRegistry& registry,
                                           const ConfigNode& parent, const std::string& key);
/// Same for a JSON object given directly (`keyPrefix` is prepended to key paths in messages).
std::unique_ptr<CureLaw> cureLawFromJson(const CureLawRegistry& registry,
                                         const nlohmann::json& section,
                                         const std::string& file = "",
                                         const std::string& keyPrefix = "");

/// The resin keys every built-in law accepts: penetration_depth or attenuation (= 1/Dp).
KeyTable resinKeyTable();
/// Penetration depth from "penetration_depth" (mm) or "attenuation" (1/mm, = 1/Dp), 0 if
/// neither. @throw InputError when both are given
double readPenetrationDepth(const KeyReader& keys);

}  // namespace vpsim::cure
