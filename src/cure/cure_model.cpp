#include "vpsim/cure/cure_model.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"

namespace vpsim::cure {
namespace {

void requirePositive(double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value)) {
        std::ostringstream reason;
        reason << name << " must be positive and finite, got " << value;
        throw InputError(reason.str());
    }
}

void requireGelPoint(double gelPoint) {
    if (!(gelPoint > 0.0 && gelPoint < 1.0)) {
        std::ostringstream reason;
        reason << "gel point Phi_c must lie strictly between 0 and 1, got " << gelPoint;
        throw InputError(reason.str());
    }
}

/// ln(1/(1 - Phi_c)): the value of K E at the gel point.
double gelExponent(double gelPoint) {
    return -std::log1p(-gelPoint);
}

}  // namespace

double jacobsCureDepth(double surfaceDose, double criticalDose, double penetrationDepth) {
    requirePositive(criticalDose, "critical dose");
    requirePositive(penetrationDepth, "penetration depth");
    if (!(surfaceDose > criticalDose)) return 0.0;
    return penetrationDepth * std::log(surfaceDose / criticalDose);
}

double fppConversion(double localDose, double rateConstant) {
    // -expm1 keeps full precision for the small conversions near the gel point.
    return -std::expm1(-rateConstant * std::max(localDose, 0.0));
}

double fppConversionAtDepth(double surfaceDose, double depth, double rateConstant,
                            double attenuation) {
    return fppConversion(surfaceDose * std::exp(-attenuation * depth), rateConstant);
}

double fppGelDose(double rateConstant, double gelPoint) {
    requirePositive(rateConstant, "rate constant K");
    requireGelPoint(gelPoint);
    return gelExponent(gelPoint) / rateConstant;
}

double fppCureDepth(double surfaceDose, double rateConstant, double attenuation, double gelPoint) {
    requirePositive(attenuation, "attenuation mu");
    double gelDose = fppGelDose(rateConstant, gelPoint);
    if (!(surfaceDose > gelDose)) return 0.0;
    // Eq. 2 as printed: Zf = ln(K d / ln(1/(1-Phi_c))) / mu.
    return std::log(rateConstant * surfaceDose / gelExponent(gelPoint)) / attenuation;
}

double fppRateConstantFromCriticalDose(double criticalDose, double gelPoint) {
    requirePositive(criticalDose, "critical dose");
    requireGelPoint(gelPoint);
    return gelExponent(gelPoint) / criticalDose;
}

CureModel CureModel::threshold(double criticalDose, double penetrationDepth) {
    requirePositive(criticalDose, "critical dose");
    if (penetrationDepth != 0.0) requirePositive(penetrationDepth, "penetration depth");
    CureModel model;
    model.mKind = CureModelKind::Threshold;
    model.mCriticalDose = criticalDose;
    model.mPenetrationDepth = penetrationDepth;
    return model;
}

CureModel CureModel::fpp(double rateConstant, double gelPoint, double penetrationDepth) {
    if (penetrationDepth != 0.0) requirePositive(penetrationDepth, "penetration depth");
    CureModel model;
    model.mKind = CureModelKind::Fpp;
    model.mCriticalDose = fppGelDose(rateConstant, gelPoint);
    model.mRateConstant = rateConstant;
    model.mGelPoint = gelPoint;
    model.mPenetrationDepth = penetrationDepth;
    return model;
}

std::string CureModel::kindName() const {
    return mKind == CureModelKind::Fpp ? "fpp" : "threshold";
}

double CureModel::conversion(double dose) const {
    if (mKind == CureModelKind::Fpp) return fppConversion(dose, mRateConstant);
    return isCured(dose) ? 1.0 : 0.0;
}

double CureModel::cureDepth(double surfaceDose) const {
    if (!hasPenetrationDepth())
        throw InputError("the " + kindName() +
                         " cure model has no penetration depth, so it gives no cure depth");
    return jacobsCureDepth(surfaceDose, mCriticalDose, mPenetrationDepth);
}

nlohmann::json CureModel::toJson() const {
    nlohmann::json out;
    out["model"] = kindName();
    if (mKind == CureModelKind::Fpp) {
        out["K"] = mRateConstant;
        out["gel_point"] = mGelPoint;
    } else {
        out["critical_dose"] = mCriticalDose;
    }
    if (hasPenetrationDepth()) out["penetration_depth"] = mPenetrationDepth;
    return out;
}

}  // namespace vpsim::cure
