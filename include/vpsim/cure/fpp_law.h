#pragma once
/// @file
/// Frontal photopolymerisation (seed 001 Eq. 1-2): local conversion Phi = 1 - exp(-K E); the
/// resin gels where Phi >= Phi_c, i.e. at E >= Ec = ln(1/(1 - Phi_c)) / K, which is the Jacobs
/// working curve with Dp = 1/mu (cure_model.h derives it).
/// Section keys: "gel_point" (Phi_c), exactly one of "K" (e.g. "0.0053 cm^2/mJ") or
/// "critical_dose", and "penetration_depth" or "attenuation" (optional).

#include "vpsim/cure/cure_law.h"

namespace vpsim::cure {

class FppLaw : public CureLaw {
public:
    /// @param rateConstant K, mm^2/mJ (> 0) @param gelPoint Phi_c in (0, 1)
    /// @param penetrationDepth Dp = 1/mu, mm (> 0, or 0 when not known)
    /// @throw InputError on a parameter out of range
    FppLaw(double rateConstant, double gelPoint, double penetrationDepth = 0.0);
    std::string name() const override { return "fpp"; }
    double criticalDose() const override { return mCriticalDose; }
    double conversion(double dose) const override;
    bool hasConversion() const override { return true; }
    std::optional<ConversionKinetics> conversionKinetics() const override {
        return ConversionKinetics{mRateConstant, mGelPoint};
    }
    /// Vectorised 1 - exp(-K E) in float (absolute error ~1e-7).
    void conversionRange(const float* dose, size_t count, float* conversion) const override;
    double penetrationDepth() const override { return mPenetrationDepth; }
    nlohmann::json toJson() const override;
    double rateConstant() const { return mRateConstant; }  ///< K, mm^2/mJ
    double gelPoint() const { return mGelPoint; }          ///< Phi_c

private:
    double mRateConstant, mGelPoint, mPenetrationDepth, mCriticalDose;
};

/// Registers "fpp".
void registerFppLaw(CureLawRegistry& registry);

}  // namespace vpsim::cure
