#pragma once
/// @file
/// Calibration of the cure model from a working curve (seed 001 Section 2.2, Table 1): samples
/// exposed to surface doses E0 and their measured cured thickness Cd. The Jacobs working curve
/// Cd = Dp ln E0 - Dp ln Ec is linear in ln E0 with slope Dp and intercept -Dp ln Ec; an ordinary
/// least-squares line gives Dp and Ec, and the gel point Phi_c gives the FPP rate constant
/// K = ln(1/(1-Phi_c)) / Ec. Standard errors come from the least-squares covariance and the delta
/// method.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vpsim/cure/cure_law.h"

namespace vpsim::cure {

/// Working-curve measurements in base units.
struct WorkingCurveData {
    std::vector<double> dose;             ///< surface dose E0, mJ/mm^2 (> 0)
    std::vector<double> cureDepth;        ///< measured cured thickness Cd, mm (> 0)
    std::vector<int> line;                ///< 1-based line of each point in the source file
    std::string file;                     ///< source file ("" when built in code)
    std::string doseColumn, depthColumn;  ///< header names of the columns used
};

/// Parses a working-curve CSV. Lines starting with '#' and blank lines are skipped; the first
/// other line is the header. The dose column is the one whose name contains "dose" or
/// "exposure", the depth column the one containing "depth", "thickness", "cd" or "zf"; each
/// name carries its unit after the first '_' ("dose_mJ_per_cm2", "thickness_mm",
/// "cure_depth_um") or in brackets ("dose [mJ/cm^2]", "Cd (mm)"). Other columns are ignored.
/// @param text file contents @param file name used in messages
/// @throw InputError naming the file, line and reason for: no header, a missing or ambiguous
///        column, a column without a unit or of the wrong dimension, a wrong cell count, a
///        non-numeric cell, a non-positive dose or depth, or fewer than 3 points
WorkingCurveData parseWorkingCurveCsv(const std::string& text, const std::string& file);

/// Reads and parses a working-curve CSV file. @throw InputError as parseWorkingCurveCsv, or when
/// the file cannot be read.
WorkingCurveData loadWorkingCurveCsv(const std::string& path);

/// Least-squares fit of Cd = slope ln(E0 / (1 mJ/mm^2)) + intercept.
struct WorkingCurveFit {
    size_t count = 0;                     ///< number of points
    double penetrationDepth = 0;          ///< Dp = slope, mm
    double penetrationDepthStderr = 0;    ///< standard error of Dp, mm
    double intercept = 0;                 ///< -Dp ln(Ec / (1 mJ/mm^2)), mm
    double interceptStderr = 0;           ///< mm
    double slopeInterceptCovariance = 0;  ///< mm^2
    double criticalDose = 0;              ///< Ec = exp(-intercept/slope), mJ/mm^2
    double lnCriticalDoseStderr = 0;      ///< standard error of ln Ec (relative error of Ec)
    double criticalDoseStderr = 0;        ///< Ec * lnCriticalDoseStderr, mJ/mm^2 (delta method)
    double rSquared = 0;                  ///< coefficient of determination
    double residualStd = 0;               ///< sqrt(SSR / (n - 2)), mm
    std::vector<double> residuals;        ///< measured - fitted Cd per point, mm

    /// Fitted cure depth (mm) for a surface dose (mJ/mm^2); may be negative below Ec.
    double predictDepth(double dose) const;
};

/// Fits the working curve. @param dose E0 (mJ/mm^2) @param cureDepth Cd (mm), same length
/// @throw InputError when fewer than 3 points, lengths differ, a dose is not positive, all doses
///        are equal, or the fitted slope Dp is not positive
WorkingCurveFit fitWorkingCurve(const std::vector<double>& dose,
                                const std::vector<double>& cureDepth);

/// FPP parameters derived from a working-curve fit and the gel point.
struct FppCalibration {
    double gelPoint = 0;            ///< Phi_c (taken as exact)
    double rateConstant = 0;        ///< K = ln(1/(1-Phi_c)) / Ec, mm^2/mJ
    double rateConstantStderr = 0;  ///< K * stderr(ln Ec), mm^2/mJ
    double attenuation = 0;         ///< mu = 1/Dp, 1/mm
    double attenuationStderr = 0;   ///< stderr(Dp) / Dp^2, 1/mm
};

/// @param gelPoint Phi_c in (0, 1) @throw InputError when out of range
FppCalibration fppFromWorkingCurve(const WorkingCurveFit& fit, double gelPoint);

/// The cure law a working curve calibrates, asked of the registry: every registered law is
/// offered the fitted values as a cure section (critical_dose, penetration_depth and, when
/// `gelPoint` is given, gel_point), and the first law (by name) whose factory takes all of them
/// is returned (fpp with a gel point, threshold without, for the built-ins).
/// @throw InputError when no registered law takes them
std::unique_ptr<CureLaw> calibratedLaw(const CureLawRegistry& registry, const WorkingCurveFit& fit,
                                       std::optional<double> gelPoint);

}  // namespace vpsim::cure
