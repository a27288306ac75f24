#pragma once
/// @file
/// Jacobs threshold law (seed 000 Section I): resin cures where the local dose E >= Ec; it
/// knows nothing in between, so its conversion is a step.
/// Section keys: "critical_dose" (dose), and "penetration_depth" or "attenuation" (optional).

#include "vpsim/cure/cure_law.h"

namespace vpsim::cure {

class ThresholdLaw : public CureLaw {
public:
    /// @param criticalDose Ec, mJ/mm^2 (> 0) @param penetrationDepth Dp, mm (> 0, or 0: none)
    /// @throw InputError on a non-positive or non-finite parameter
    ThresholdLaw(double criticalDose, double penetrationDepth = 0.0);
    std::string name() const override { return "threshold"; }
    double criticalDose() const override { return mCriticalDose; }
    double conversion(double dose) const override { return isCured(dose) ? 1.0 : 0.0; }
    bool hasConversion() const override { return false; }
    double penetrationDepth() const override { return mPenetrationDepth; }
    nlohmann::json toJson() const override;

private:
    double mCriticalDose, mPenetrationDepth;
};

/// Registers "threshold".
void registerThresholdLaw(CureLawRegistry& registry);

}  // namespace vpsim::cure
