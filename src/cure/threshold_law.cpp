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
    registry.add({"threshold", "Jacobs threshold: cured where the local dose reaches Ec",
                  KeyTable({quantityKey("critical_dose", dim::DOSE, nullptr, "Ec")
                                .positiveOnly()
                                .requiredLike("10 mJ/cm^2")})
                      .add(resinKeyTable()),
                  [](const KeyReader& keys) {
                      double dp = readPenetrationDepth(keys);
                      return std::make_unique<ThresholdLaw>(keys.quantity("critical_dose"), dp);
                  }});
}

}  // namespace vpsim::cure
