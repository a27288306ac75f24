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

std::unique_ptr<CureLaw> fppFromKeys(const KeyReader& keys) {
    double penetrationDepth = readPenetrationDepth(keys);
    double gelPoint = keys.number("gel_point");
    bool hasK = keys.has("K"), hasEc = keys.has("critical_dose");
    if (hasK == hasEc)
        throw keys.error(
            "K", "the fpp model needs exactly one of K (e.g. \"0.0053 cm^2/mJ\") or critical_dose");
    double rateConstant =
        hasK ? *keys.optionalQuantity("K")
             : fppRateConstantFromCriticalDose(*keys.optionalQuantity("critical_dose"), gelPoint);
    return std::make_unique<FppLaw>(rateConstant, gelPoint, penetrationDepth);
}

KeyTable fppKeyTable() {
    KeyTable table({
        numberKey("gel_point", nullptr, "Phi_c, the conversion at gelation")
            .in(1e-9, 1.0 - 1e-9)
            .requiredLike(0.276),
        quantityKey("K", dim::INVERSE_DOSE, nullptr,
                    "rate constant (exactly one of K and critical_dose)")
            .positiveOnly()
            .withExample("0.0053 cm^2/mJ"),
        quantityKey("critical_dose", dim::DOSE, nullptr,
                    "Ec instead of K: then K = ln(1/(1 - Phi_c)) / Ec")
            .positiveOnly(),
    });
    return table.add(resinKeyTable());
}

}  // namespace

void registerFppLaw(CureLawRegistry& registry) {
    registry.add({"fpp",
                  "frontal photopolymerisation (seed 001 Eq. 1-2): conversion 1 - exp(-K E), "
                  "cured at the gel point",
                  fppKeyTable(), fppFromKeys});
}

}  // namespace vpsim::cure
