#include "vpsim/cure/cure_model.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vpsim/core/checks.h"
#include "vpsim/core/error.h"

namespace vpsim::cure {
namespace {

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

}  // namespace vpsim::cure
