#include "vpsim/cure/fpp_law.h"

#include <nlohmann/json.hpp>

#include "conversion_kernel.h"
#include "vpsim/core/checks.h"
#include "vpsim/cure/cure_model.h"

namespace vpsim::cure {

FppLaw::FppLaw(double rateConstant, double gelPoint, double penetrationDepth)
    : mRateConstant(rateConstant), mGelPoint(gelPoint), mPenetrationDepth(penetrationDepth) {
    if (penetrationDepth != 0.0) requirePositive(penetrationDepth, "penetration depth");
    mCriticalDose = fppGelDose(rateConstant, gelPoint);  // checks K and Phi_c
}

double FppLaw::conversion(double dose) const {
    return fppConversion(dose, mRateConstant);
}

void FppLaw::conversionRange(const float* dose, size_t count, float* conversion) const {
    detail::fppConversionRange(dose, count, float(mRateConstant), conversion);
}

nlohmann::json FppLaw::toJson() const {
    nlohmann::json out{{"model", name()}, {"K", mRateConstant}, {"gel_point", mGelPoint}};
    if (hasPenetrationDepth()) out["penetration_depth"] = mPenetrationDepth;
    return out;
}

namespace {

std::unique_ptr<CureLaw> fppFromSection(const ConfigNode& node) {
    double penetrationDepth = readPenetrationDepth(node);
    double gelPoint = node.number("gel_point");
    if (!(gelPoint > 0.0 && gelPoint < 1.0))
        throw node.error("gel_point", "the gel point Phi_c must lie strictly between 0 and 1");
    bool hasK = node.has("K"), hasEc = node.has("critical_dose");
    if (hasK == hasEc)
        throw node.error(
            "K", "the fpp model needs exactly one of K (e.g. \"0.0053 cm^2/mJ\") or critical_dose");
    double rateConstant = hasK ? positiveQuantity(node, "K", dim::INVERSE_DOSE)
                               : fppRateConstantFromCriticalDose(
                                     positiveQuantity(node, "critical_dose", dim::DOSE), gelPoint);
    return std::make_unique<FppLaw>(rateConstant, gelPoint, penetrationDepth);
}

}  // namespace

void registerFppLaw(CureLawRegistry& registry) {
    registry.add({"fpp",
                  "frontal photopolymerisation (seed 001 Eq. 1-2): conversion 1 - exp(-K E), "
                  "cured at the gel point",
                  {{"gel_point", "Phi_c in (0, 1)"},
                   {"K", "rate constant (inverse dose, e.g. \"0.0053 cm^2/mJ\"); or critical_dose"},
                   {"critical_dose", "Ec (dose); then K = ln(1/(1 - Phi_c)) / Ec"},
                   {"penetration_depth", "Dp (length), optional; or attenuation = 1/Dp"}},
                  fppFromSection});
}

}  // namespace vpsim::cure
