// Working-curve calibration: exact synthetic recovery, a hand-computed regression, CSV errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "vpsim/core/error.h"
#include "vpsim/cure/calibration.h"
#include "vpsim/cure/cure_model.h"

using namespace vpsim;
using namespace vpsim::cure;

TEST_CASE("Calibration recovers the parameters of exact synthetic data", "[cure]") {
    // Cd = Dp ln(E0/Ec) exactly; the fit must return Dp and Ec to rounding (1e-9 relative).
    const double dp = 0.2537, ec = 0.4321, gel = 0.276;
    std::vector<double> dose, depth;
    for (double e = 0.5; e < 30.0; e *= 1.37) {
        dose.push_back(e);
        depth.push_back(dp * std::log(e / ec));
    }
    WorkingCurveFit fit = fitWorkingCurve(dose, depth);
    REQUIRE(fit.count == dose.size());
    REQUIRE(fit.penetrationDepth == Approx(dp).epsilon(1e-9));
    REQUIRE(fit.criticalDose == Approx(ec).epsilon(1e-9));
    REQUIRE(fit.rSquared == Approx(1.0).epsilon(1e-12));
    REQUIRE(fit.penetrationDepthStderr < 1e-9);
    REQUIRE(fit.criticalDoseStderr < 1e-9);
    FppCalibration fpp = fppFromWorkingCurve(fit, gel);
    REQUIRE(fpp.rateConstant == Approx(-std::log(1.0 - gel) / ec).epsilon(1e-9));
    REQUIRE(fpp.attenuation == Approx(1.0 / dp).epsilon(1e-9));
    // The FPP model built from the fit reproduces the synthetic depths (Eq. 2).
    for (size_t i = 0; i < dose.size(); ++i)
        if (depth[i] > 0.0)
            REQUIRE(fppCureDepth(dose[i], fpp.rateConstant, fpp.attenuation, gel) ==
                    Approx(depth[i]).epsilon(1e-9).margin(1e-12));
}

TEST_CASE("Calibration standard errors match a hand-computed regression", "[cure]") {
    // ln E0 = 0, 1, 2, 3 and Cd = 0.10, 0.45, 0.75, 1.10 mm. By hand: mean x 1.5, Sxx 5,
    // mean y 0.6, Sxy 1.65 -> slope 0.33, intercept 0.105; residuals -0.005, 0.015, -0.015, 0.005;
    // SSR 5e-4, s^2 = SSR/2 = 2.5e-4; var(slope) = s^2/Sxx = 5e-5; var(intercept) =
    // s^2 (1/4 + 1.5^2/5) = 1.75e-4; cov = -1.5 s^2/5 = -7.5e-5; SST 0.545.
    std::vector<double> dose = {1.0, std::exp(1.0), std::exp(2.0), std::exp(3.0)};
    std::vector<double> depth = {0.10, 0.45, 0.75, 1.10};
    WorkingCurveFit fit = fitWorkingCurve(dose, depth);
    // Tolerance 1e-12: the hand values are exact decimals, the fit adds only rounding.
    REQUIRE(fit.penetrationDepth == Approx(0.33).epsilon(1e-12));
    REQUIRE(fit.intercept == Approx(0.105).epsilon(1e-12));
    REQUIRE(fit.penetrationDepthStderr == Approx(std::sqrt(5e-5)).epsilon(1e-12));
    REQUIRE(fit.interceptStderr == Approx(std::sqrt(1.75e-4)).epsilon(1e-12));
    REQUIRE(fit.slopeInterceptCovariance == Approx(-7.5e-5).epsilon(1e-12));
    REQUIRE(fit.rSquared == Approx(1.0 - 5e-4 / 0.545).epsilon(1e-12));
    REQUIRE(fit.residualStd == Approx(std::sqrt(2.5e-4)).epsilon(1e-12));
    std::vector<double> residuals = {-0.005, 0.015, -0.015, 0.005};
    for (int i = 0; i < 4; ++i) REQUIRE(fit.residuals[i] == Approx(residuals[i]).margin(1e-14));
    // ln Ec = -b/s = -0.105/0.33; delta method with gradient g = (b/s^2, -1/s):
    // var = g1^2 5e-5 + g2^2 1.75e-4 + 2 g1 g2 (-7.5e-5).
    const double g1 = 0.105 / (0.33 * 0.33), g2 = -1.0 / 0.33;
    const double varLnEc = g1 * g1 * 5e-5 + g2 * g2 * 1.75e-4 + 2.0 * g1 * g2 * -7.5e-5;
    REQUIRE(fit.criticalDose == Approx(std::exp(-0.105 / 0.33)).epsilon(1e-12));
    REQUIRE(fit.lnCriticalDoseStderr == Approx(std::sqrt(varLnEc)).epsilon(1e-10));
    REQUIRE(fit.criticalDoseStderr ==
            Approx(std::exp(-0.105 / 0.33) * std::sqrt(varLnEc)).epsilon(1e-10));
    FppCalibration fpp = fppFromWorkingCurve(fit, 0.276);
    REQUIRE(fpp.rateConstantStderr == Approx(fpp.rateConstant * std::sqrt(varLnEc)).epsilon(1e-10));
    REQUIRE(fpp.attenuationStderr == Approx(std::sqrt(5e-5) / (0.33 * 0.33)).epsilon(1e-12));
}

TEST_CASE("Working-curve CSV: units from the header", "[cure]") {
    WorkingCurveData a = parseWorkingCurveCsv(
        "# comment\n\ndose_mJ_per_cm2,thickness_mm\n100,0.2\r\n200,0.4\n400,0.6\n", "a.csv");
    REQUIRE(a.dose == std::vector<double>{1.0, 2.0, 4.0});  // mJ/cm^2 -> mJ/mm^2 (exact /100)
    REQUIRE(a.cureDepth[2] == 0.6);
    REQUIRE(a.line == std::vector<int>{4, 5, 6});
    REQUIRE(a.doseColumn == "dose_mJ_per_cm2");
    WorkingCurveData b = parseWorkingCurveCsv(
        "sample,Cd (um),Exposure [mJ/mm^2]\nS1,200,1\nS2,400,2\nS3,600,4\n", "b.csv");
    REQUIRE(b.dose == std::vector<double>{1.0, 2.0, 4.0});
    REQUIRE(b.cureDepth[0] == Approx(0.2).epsilon(1e-15));
    WorkingCurveData c =
        parseWorkingCurveCsv("cure_depth_um,dose_J_per_cm2\n200,1\n400,2\n600,4\n", "c.csv");
    REQUIRE(c.dose[0] == Approx(10.0).epsilon(1e-15));  // 1 J/cm^2 = 10 mJ/mm^2
}

namespace {

std::string csvError(const std::string& text) {
    try {
        parseWorkingCurveCsv(text, "wc.csv");
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}

}  // namespace

TEST_CASE("Malformed working-curve CSVs give one clear error naming file, line and reason",
          "[cure]") {
    using Catch::Contains;
    const std::string header = "dose_mJ_per_cm2,thickness_mm\n";
    CHECK_THAT(csvError("dose_mJ_per_cm2,width_mm\n1,2\n"),
               Contains("wc.csv:1") && Contains("no cure depth column"));
    CHECK_THAT(csvError("time_s,thickness_mm\n1,2\n"), Contains("no dose column"));
    CHECK_THAT(csvError("dose,thickness_mm\n1,2\n"), Contains("'dose' carries no dose"));
    CHECK_THAT(csvError("dose_mm,thickness_mm\n1,2\n"), Contains("carries no dose"));
    CHECK_THAT(csvError("dose_mJ_per_cm2,exposure_mJ_per_cm2,thickness_mm\n"),
               Contains("more than one dose"));
    CHECK_THAT(csvError(header + "104,0.19\n156,abc\n260,0.5\n"),
               Contains("wc.csv:3") && Contains("non-numeric cell 'abc'"));
    CHECK_THAT(csvError(header + "104,0.19\n156\n260,0.5\n"),
               Contains("wc.csv:3") && Contains("expected 2 cells"));
    CHECK_THAT(csvError(header + "104,0.19\n,0.3\n260,0.5\n"),
               Contains("wc.csv:3") && Contains("empty cell"));
    CHECK_THAT(csvError(header + "104,0.19\n0,0.3\n260,0.5\n"),
               Contains("wc.csv:3") && Contains("dose must be positive"));
    CHECK_THAT(csvError(header + "104,0.19\n-5,0.3\n260,0.5\n"), Contains("dose must be positive"));
    CHECK_THAT(csvError(header + "104,0.19\n156,0\n260,0.5\n"),
               Contains("cure depth must be positive"));
    CHECK_THAT(csvError(header + "104,0.19\n156,0.3\n"),
               Contains("wc.csv:3") && Contains("at least 3"));
    CHECK_THAT(csvError("# only comments\n"), Contains("wc.csv") && Contains("no header"));
    CHECK_THAT(csvError(header + "1e999,0.2\n2,0.3\n3,0.4\n"), Contains("out of range"));
}

TEST_CASE("Working-curve files: missing file and degenerate data", "[cure]") {
    REQUIRE_THROWS_WITH(loadWorkingCurveCsv("/nonexistent/wc.csv"),
                        Catch::Contains("/nonexistent/wc.csv"));
    // A file on disk: the message names its path.
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / "vpsim_test_cure_bad_wc.csv";
    {
        std::ofstream out(path);
        out << "dose_mJ_per_cm2,thickness_mm\n100,0.2\n200,x\n";
    }
    REQUIRE_THROWS_WITH(loadWorkingCurveCsv(path.string()), Catch::Contains(path.string() + ":3"));
    std::filesystem::remove(path);
    // All doses equal, depth falling with dose, too few points, mismatched lengths.
    REQUIRE_THROWS_WITH(fitWorkingCurve({1, 1, 1}, {0.1, 0.2, 0.3}),
                        Catch::Contains("all doses are equal"));
    REQUIRE_THROWS_WITH(fitWorkingCurve({1, 2, 4}, {0.3, 0.2, 0.1}),
                        Catch::Contains("does not grow"));
    REQUIRE_THROWS_AS(fitWorkingCurve({1, 2}, {0.1, 0.2}), InputError);
    REQUIRE_THROWS_AS(fitWorkingCurve({1, 2, 3}, {0.1, 0.2}), InputError);
    REQUIRE_THROWS_AS(fppFromWorkingCurve(fitWorkingCurve({1, 2, 4}, {0.1, 0.2, 0.3}), 1.0),
                      InputError);
}
