#include "vpsim/cure/calibration.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"

namespace vpsim::cure {

double WorkingCurveFit::predictDepth(double dose) const {
    return penetrationDepth * std::log(dose) + intercept;
}

WorkingCurveFit fitWorkingCurve(const std::vector<double>& dose,
                                const std::vector<double>& cureDepth) {
    if (dose.size() != cureDepth.size())
        throw InputError("working curve: " + std::to_string(dose.size()) + " doses but " +
                         std::to_string(cureDepth.size()) + " depths");
    const size_t n = dose.size();
    if (n < 3)
        throw InputError("working curve: at least 3 points are needed, got " + std::to_string(n));
    std::vector<double> x(n);
    for (size_t i = 0; i < n; ++i) {
        if (!(dose[i] > 0.0) || !std::isfinite(dose[i]) || !std::isfinite(cureDepth[i])) {
            std::ostringstream reason;
            reason << "working curve: point " << i << " has dose " << dose[i] << " and depth "
                   << cureDepth[i] << "; doses must be positive and finite";
            throw InputError(reason.str());
        }
        x[i] = std::log(dose[i]);
    }
    // Ordinary least squares on centred sums (numerically stable).
    double meanX = 0.0, meanY = 0.0;
    for (size_t i = 0; i < n; ++i) {
        meanX += x[i];
        meanY += cureDepth[i];
    }
    meanX /= double(n);
    meanY /= double(n);
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double dx = x[i] - meanX, dy = cureDepth[i] - meanY;
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
    }
    if (!(sxx > 0.0))
        throw InputError("working curve: all doses are equal, so no slope can be fitted");
    WorkingCurveFit fit;
    fit.count = n;
    const double slope = sxy / sxx;
    if (!(slope > 0.0)) {
        std::ostringstream reason;
        reason << "working curve: cure depth does not grow with dose (fitted slope Dp = " << slope
               << " mm)";
        throw InputError(reason.str());
    }
    fit.penetrationDepth = slope;
    fit.intercept = meanY - slope * meanX;

    double ssr = 0.0;
    fit.residuals.resize(n);
    for (size_t i = 0; i < n; ++i) {
        fit.residuals[i] = cureDepth[i] - (slope * x[i] + fit.intercept);
        ssr += fit.residuals[i] * fit.residuals[i];
    }
    fit.rSquared = syy > 0.0 ? 1.0 - ssr / syy : 1.0;
    const double variance = ssr / double(n - 2);  // residual variance, n - 2 degrees of freedom
    fit.residualStd = std::sqrt(variance);

    // Covariance of (slope, intercept): sigma^2 (X^T X)^-1.
    const double varSlope = variance / sxx;
    const double varIntercept = variance * (1.0 / double(n) + meanX * meanX / sxx);
    fit.slopeInterceptCovariance = -variance * meanX / sxx;
    fit.penetrationDepthStderr = std::sqrt(varSlope);
    fit.interceptStderr = std::sqrt(varIntercept);

    // ln Ec = -intercept / slope; delta method with gradient (intercept/slope^2, -1/slope).
    const double lnEc = -fit.intercept / slope;
    const double gSlope = fit.intercept / (slope * slope), gIntercept = -1.0 / slope;
    const double varLnEc = gSlope * gSlope * varSlope + gIntercept * gIntercept * varIntercept +
                           2.0 * gSlope * gIntercept * fit.slopeInterceptCovariance;
    fit.criticalDose = std::exp(lnEc);
    fit.lnCriticalDoseStderr = std::sqrt(std::max(varLnEc, 0.0));
    fit.criticalDoseStderr = fit.criticalDose * fit.lnCriticalDoseStderr;
    return fit;
}

FppCalibration fppFromWorkingCurve(const WorkingCurveFit& fit, double gelPoint) {
    FppCalibration out;
    out.gelPoint = gelPoint;
    out.rateConstant = fppRateConstantFromCriticalDose(fit.criticalDose, gelPoint);  // checks Phi_c
    // K = ln(1/(1-Phi_c)) / Ec: the relative error of K is that of Ec (Phi_c taken as exact).
    out.rateConstantStderr = out.rateConstant * fit.lnCriticalDoseStderr;
    out.attenuation = 1.0 / fit.penetrationDepth;
    out.attenuationStderr =
        fit.penetrationDepthStderr / (fit.penetrationDepth * fit.penetrationDepth);
    return out;
}

std::unique_ptr<CureLaw> calibratedLaw(const CureLawRegistry& registry, const WorkingCurveFit& fit,
                                       std::optional<double> gelPoint) {
    nlohmann::json section{{"critical_dose", fit.criticalDose},
                           {"penetration_depth", fit.penetrationDepth}};
    if (gelPoint) section["gel_point"] = *gelPoint;
    std::string refusals;
    for (const std::string& name : registry.names()) {
        nlohmann::json candidate = section;
        candidate["model"] = name;
        try {
            return cureLawFromJson(registry, candidate);
        } catch (const InputError& e) {
            refusals += (refusals.empty() ? "" : "; ") + name + ": " + e.reason();
        }
    }
    throw InputError("no registered cure law takes the calibrated values (" + refusals + ")");
}

}  // namespace vpsim::cure
