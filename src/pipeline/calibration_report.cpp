#include "vpsim/pipeline/calibration_report.h"

#include <memory>

namespace vpsim::pipeline {
namespace {

constexpr double PER_MM2_TO_PER_CM2 = 100.0;  // mJ/mm^2 -> mJ/cm^2
constexpr double MM2_TO_CM2 = 0.01;           // mm^2/mJ -> cm^2/mJ

}  // namespace

nlohmann::json calibrationJson(const Builtins& builtins, const cure::WorkingCurveData& data,
                               const cure::WorkingCurveFit& fit, std::optional<double> gelPoint) {
    using namespace cure;
    nlohmann::json out;
    out["dose_column"] = data.doseColumn;
    out["depth_column"] = data.depthColumn;
    out["n_points"] = fit.count;
    out["penetration_depth_mm"] = fit.penetrationDepth;
    out["penetration_depth_mm_stderr"] = fit.penetrationDepthStderr;
    out["critical_dose_mJ_per_cm2"] = fit.criticalDose * PER_MM2_TO_PER_CM2;
    out["critical_dose_mJ_per_cm2_stderr"] = fit.criticalDoseStderr * PER_MM2_TO_PER_CM2;
    out["r_squared"] = fit.rSquared;
    out["residual_std_mm"] = fit.residualStd;
    out["residuals_mm"] = fit.residuals;  // measured - fitted, in file order
    const std::unique_ptr<CureLaw> law = calibratedLaw(builtins.cureLaws, fit, gelPoint);
    if (law->conversionKinetics()) {  // the rate constant's and attenuation's standard errors
        FppCalibration kinetics = fppFromWorkingCurve(fit, gelPoint.value_or(0.0));
        out["gel_point"] = gelPoint.value_or(0.0);
        out["K_cm2_per_mJ"] = kinetics.rateConstant * MM2_TO_CM2;
        out["K_cm2_per_mJ_stderr"] = kinetics.rateConstantStderr * MM2_TO_CM2;
        out["attenuation_per_mm"] = kinetics.attenuation;
        out["attenuation_per_mm_stderr"] = kinetics.attenuationStderr;
    }
    const nlohmann::json model = law->toJson();  // base units, read back by the cure section
    out["cure_model"] = model;                   // ready to paste into a material's cure section
    nlohmann::json points = nlohmann::json::array();
    for (size_t i = 0; i < fit.count; ++i)
        points.push_back({{"line", data.line[i]},
                          {"dose_mJ_per_cm2", data.dose[i] * PER_MM2_TO_PER_CM2},
                          {"depth_mm", data.cureDepth[i]},
                          {"fitted_mm", fit.predictDepth(data.dose[i])},
                          {"residual_mm", fit.residuals[i]}});
    out["points"] = points;
    return out;
}

}  // namespace vpsim::pipeline
