#include "vpsim/cure/threshold_law.h"

#include <nlohmann/json.hpp>

#include "vpsim/core/checks.h"

namespace vpsim::cure {

ThresholdLaw::ThresholdLaw(double criticalDose, double penetrationDepth)
    : mCriticalDose(criticalDose), mPenetrationDepth(penetrationDepth) {
    requirePositive(criticalDose, "critical dose");
    if (penetrationDepth != 0.0) requirePositive(penetrationDepth, "penetration depth");
}

nlohmann::json ThresholdLaw::toJson() const {
    nlohmann::json out{{"model", name()}, {"critical_dose", mCriticalDose}};
    if (hasPenetrationDepth()) out["penetration_depth"] = mPenetrationDepth;
    return out;
}

void registerThresholdLaw(CureLawRegistry& registry) {
    registry.add({"threshold",
                  "Jacobs threshold: cured where the local dose reaches Ec",
                  {{"critical_dose", "Ec (dose, e.g. \"10 mJ/cm^2\")"},
                   {"penetration_depth", "Dp (length), optional; or attenuation = 1/Dp"}},
                  [](const ConfigNode& section) {
                      double dp = readPenetrationDepth(section);
                      return std::make_unique<ThresholdLaw>(
                          positiveQuantity(section, "critical_dose", dim::DOSE), dp);
                  }});
}

}  // namespace vpsim::cure
