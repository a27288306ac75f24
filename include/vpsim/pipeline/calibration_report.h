#pragma once
/// @file
/// The figures of `vpsim calibrate --json` (and the Python module's vpsim.calibrate): the
/// working-curve fit with standard errors, the FPP kinetics when the calibrated law has them,
/// the cure section to paste into a job, and every point with its fitted depth.

#include <optional>

#include <nlohmann/json.hpp>

#include "vpsim/cure/calibration.h"
#include "vpsim/pipeline/builtins.h"

namespace vpsim::pipeline {

/// The calibration document (doses in mJ/cm^2, depths in mm, K in cm^2/mJ; keys as the CLI's
/// except "working_curve", the file, which the caller adds).
/// @throw InputError from the registry when no cure law takes the fit
nlohmann::json calibrationJson(const Builtins& builtins, const cure::WorkingCurveData& data,
                               const cure::WorkingCurveFit& fit, std::optional<double> gelPoint);

}  // namespace vpsim::pipeline
