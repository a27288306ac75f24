// Seed 001 Table 1 calibration against the figures the paper states.
//
// The paper does not print its fitted Dp (1/mu), Ec or K. It states (Section 2.2, 3.2, 4.4, 5.2):
//  - Table 1 means and deviations of the cured thickness at each dose;
//  - the gel point Phi_c = 0.276;
//  - "a minimum photoconversion value ... around 0.939 for a layer thickness of 50 microns",
//    the conversion left by the bonding dose d_min of Eq. 10 (n_z = 1) applied to every layer;
//  - that a uniform 78 mJ/cm^2 per layer gives "a photoconversion ratio mean of solidified parts
//    similar to the objective input (0.95)";
//  - Table 2: measured Z dimensions of non-optimised parts, whose down-facing surfaces grew by
//    print-through; its model predicted them with mean error -0.06 mm and sd 0.11 mm (Fig. 21).
// These depend on the fitted mu and K, so each is a check of our calibration.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "vpsim/core/io.h"
#include "vpsim/cure/calibration.h"
#include "vpsim/cure/cure_model.h"
#include "vpsim/cure/fpp_law.h"
#include "vpsim/cure/print_through.h"

using namespace vpsim;
using namespace vpsim::cure;

namespace {

const std::string TABLE1 =
    std::string(VPSIM_SOURCE_DIR) + "/tests/data/reference/seed001_table1_working_curve.csv";
const std::string TABLE2 =
    std::string(VPSIM_SOURCE_DIR) + "/tests/data/reference/seed001_table2_z_dimensions.csv";
constexpr double GEL_POINT = 0.276;
constexpr double LAYER = 0.05;  // mm, seed 001 Section 4.1 / 5.1

WorkingCurveFit table1Fit() {
    WorkingCurveData data = loadWorkingCurveCsv(TABLE1);
    REQUIRE(data.dose.size() == 15);
    return fitWorkingCurve(data.dose, data.cureDepth);
}

/// Steady-state accumulated dose range over one layer deep inside a part printed with dose d per
/// layer: top of a layer d / (1 - a), bottom a d / (1 - a), a = exp(-Le/Dp). Computed with the
/// print-through column (200 layers: a^200 < 1e-11) rather than the closed form.
std::pair<double, double> steadyDoseRange(double perLayerDose, double dp) {
    std::vector<double> stack(200, perLayerDose);
    return {accumulatedBottomDoses(stack, LAYER, dp)[0],
            accumulatedLayerDoses(stack, LAYER, dp)[0]};
}

}  // namespace

TEST_CASE("Table 1 calibration: fitted values", "[cure]") {
    WorkingCurveFit fit = table1Fit();
    FppCalibration fpp = fppFromWorkingCurve(fit, GEL_POINT);
    // Reference values from an independent least-squares computation (Python, closed-form OLS on
    // the 15 points): Dp 0.365936 mm, Ec 61.1581 mJ/cm^2, K 0.00528080 cm^2/mJ,
    // se(Dp) 0.0025402 mm, r^2 0.999374. Tolerance 1e-5 relative: the reference is printed to
    // 6 figures.
    REQUIRE(fit.penetrationDepth == Approx(0.36593587).epsilon(1e-5));
    REQUIRE(fit.criticalDose * 100.0 == Approx(61.158109).epsilon(1e-5));
    REQUIRE(fpp.rateConstant / 100.0 == Approx(0.0052808024).epsilon(1e-5));
    REQUIRE(fit.penetrationDepthStderr == Approx(0.00254018).epsilon(1e-5));
    REQUIRE(fit.rSquared == Approx(0.99937398).epsilon(1e-6));
    // "the attenuation factor is calculated as the inverse of the experimental slope" (Sec. 2.2)
    REQUIRE(fpp.attenuation == Approx(1.0 / fit.penetrationDepth).epsilon(1e-15));
}

TEST_CASE("Table 1 calibration reproduces the paper's mean thicknesses within its deviations",
          "[cure]") {
    // Table 1's Mean and Deviation columns: the fitted curve must pass within 2 deviations of each
    // mean (2 sd of one sample is a ~95% band; the means themselves are tighter, the rest is the
    // departure of the real resin from a straight line in ln E, at most 1.9 deviations here).
    WorkingCurveFit fit = table1Fit();
    struct Row {
        double doseMjPerCm2, mean, deviation;
    };
    for (Row row : {Row{104, 0.193, 0.009}, Row{156, 0.337, 0.003}, Row{260, 0.537, 0.007},
                    Row{416, 0.705, 0.009}, Row{1040, 1.033, 0.003}}) {
        INFO("dose " << row.doseMjPerCm2 << " mJ/cm^2");
        REQUIRE(fit.predictDepth(row.doseMjPerCm2 / 100.0) ==
                Approx(row.mean).margin(2.0 * row.deviation));
    }
}

TEST_CASE("Table 1 calibration gives the paper's minimum photoconversion 0.939 at 50 um layers",
          "[cure]") {
    // Eq. 10 with n_z = 1: d_min = exp(mu Le) ln(1/(1-Phi_c)) / K bonds each layer to the one
    // below. With d_min on every layer the conversion inside the part varies over each layer
    // between the bottom and top accumulated doses. The paper's 0.939 must lie in that range; the
    // range is narrow ([0.920, 0.945] with our fit) and moves with mu: Dp = 0.30 mm or 0.45 mm
    // would put 0.939 outside, so the check constrains the fitted attenuation.
    WorkingCurveFit fit = table1Fit();
    FppLaw resin(fppFromWorkingCurve(fit, GEL_POINT).rateConstant, GEL_POINT, fit.penetrationDepth);
    const double dMin = std::exp(LAYER / fit.penetrationDepth) * resin.criticalDose();
    auto [bottom, top] = steadyDoseRange(dMin, fit.penetrationDepth);
    INFO("conversion range over a layer: " << resin.conversion(bottom) << " .. "
                                           << resin.conversion(top));
    REQUIRE(resin.conversion(bottom) <= 0.939);
    REQUIRE(resin.conversion(top) >= 0.939);
}

TEST_CASE("Table 1 calibration: uniform 78 mJ/cm^2 layers give conversion about 0.95", "[cure]") {
    // Section 4.4: 78 mJ/cm^2 per layer was chosen so the mean conversion of solidified parts is
    // similar to 0.95. Our fit gives 0.940 .. 0.960 over a layer deep in the part; the paper's
    // figure must lie in that range. This checks K (through Ec) as well as mu.
    WorkingCurveFit fit = table1Fit();
    FppLaw resin(fppFromWorkingCurve(fit, GEL_POINT).rateConstant, GEL_POINT, fit.penetrationDepth);
    auto [bottom, top] = steadyDoseRange(0.78, fit.penetrationDepth);
    INFO("conversion range over a layer: " << resin.conversion(bottom) << " .. "
                                           << resin.conversion(top));
    REQUIRE(resin.conversion(bottom) <= 0.95);
    REQUIRE(resin.conversion(top) >= 0.95);
}

TEST_CASE("Table 1 calibration predicts the print-through growth of Table 2's non-optimised parts",
          "[cure]") {
    // A down-facing surface (bottom of a hole or overhang) under a stack of layers exposed at a
    // uniform 78 mJ/cm^2 receives the accumulated bottom dose of the lowest layer; resin below it
    // cures to the Jacobs depth Dp ln(D / Ec). The part geometry above each surface is in figures
    // lost from the text, so we take 2 mm of part above (40 layers; a taller part adds < 1 um).
    // Measured growth = |measured - objective| for S1-S6 (holes shrink, overhangs thicken).
    // The paper's own model missed its prints by mean -0.06 mm, sd 0.11 mm (Section 5.2), so we
    // require our prediction within 0.06 + 2 x 0.11 = 0.28 mm of the measured mean growth.
    WorkingCurveFit fit = table1Fit();
    const double bottomDose =
        accumulatedBottomDoses(std::vector<double>(40, 0.78), LAYER, fit.penetrationDepth)[0];
    const double predicted = jacobsCureDepth(bottomDose, fit.criticalDose, fit.penetrationDepth);

    std::istringstream table(readFile(TABLE2));
    std::string line;
    double sum = 0.0;
    int count = 0;
    while (std::getline(table, line)) {
        if (line.empty() || line[0] == '#' || line.rfind("sample", 0) == 0) continue;
        std::vector<std::string> cells;
        std::stringstream row(line);
        for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
        REQUIRE(cells.size() == 7);
        if (cells[2] != "non-optimised") continue;
        sum += std::abs(std::stod(cells[3]) - std::stod(cells[4])) +
               std::abs(std::stod(cells[5]) - std::stod(cells[6]));
        count += 2;
    }
    REQUIRE(count == 12);
    const double measured = sum / count;  // 0.663 mm
    INFO("predicted growth " << predicted << " mm, measured mean " << measured << " mm");
    REQUIRE(predicted == Approx(measured).margin(0.28));
}
