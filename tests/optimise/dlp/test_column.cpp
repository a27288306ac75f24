// DLP column dose optimisation (seed 001 Eq. 5-12): transmission matrix, bonding dose, the convex
// per-pattern solve against closed forms and KKT conditions, and the pattern search.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "dlp_test_support.h"
#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"
#include "vpsim/cure/print_through.h"
#include "vpsim/optimise/dlp/column.h"

using namespace vpsim;
using namespace vpsim::optimise;

namespace {

/// The seed 001 resin as calibrated from Table 1 (test_seed001_calibration.cpp), 50 um layers.
DlpColumnProblem seedResin(double maxDose) {
    return vpsim::test::seedResin(maxDose,
                                  Bonding::RunBottom);  // the reading these tests were written for
}

const double GEL = 0.3229638865964207;  // ln(1/(1-0.276)), computed independently

}  // namespace

TEST_CASE("DLP: bonding dose (Eq. 10) and transmission matrix (Eq. 7) by hand", "[cure]") {
    // mu Le = ln 2 makes every attenuation factor a power of 1/2: exact in binary (tolerance
    // 1e-15).
    const double le = std::log(2.0);
    REQUIRE(bondingDose(1.0, 1.0, 0.276, le) == Approx(2.0 * GEL).epsilon(1e-15));
    REQUIRE(bondingDose(1.0, 1.0, 0.276, le, 2) == Approx(4.0 * GEL).epsilon(1e-15));
    REQUIRE(bondingDose(0.5, 1.0, 0.276, le) == Approx(4.0 * GEL).epsilon(1e-15));
    std::vector<double> t = transmissionMatrix(3, le, 1.0, 1.0);
    std::vector<double> expected = {-1, -0.5, -0.25, 0, -1, -0.5, 0, 0, -1};
    for (int i = 0; i < 9; ++i) REQUIRE(t[i] == Approx(expected[i]).margin(1e-15));
    REQUIRE_THROWS_AS(bondingDose(1.0, 1.0, 0.276, le, 0), InputError);
}

TEST_CASE("DLP: O(n) products equal the dense transmission matrix", "[cure]") {
    // Same sums in a different order: 1e-12 relative.
    const size_t n = 50;
    const double le = 0.05, k = 0.528, mu = 2.73;
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> uniform(0.0, 2.0);
    std::vector<double> d(n), v(n);
    for (size_t i = 0; i < n; ++i) d[i] = uniform(rng), v[i] = uniform(rng) - 1.0;
    std::vector<double> t = transmissionMatrix(n, le, k, mu);
    std::vector<double> td = applyTransmission(d, le, k, mu),
                        ttv = applyTransmissionTransposed(v, le, k, mu);
    for (size_t p = 0; p < n; ++p) {
        double rowSum = 0.0, columnSum = 0.0;
        for (size_t r = 0; r < n; ++r) {
            rowSum += t[p * n + r] * d[r];
            columnSum += t[r * n + p] * v[r];
        }
        REQUIRE(td[p] == Approx(rowSum).epsilon(1e-12));
        REQUIRE(ttv[p] == Approx(columnSum).epsilon(1e-12).margin(1e-14));
    }
    // Eq. 6: Phi = 1 - exp(phi) reproduces Eq. 1 plus print-through for one exposure.
    std::vector<double> single = {0.0, 0.0, 1.7};
    REQUIRE(-std::expm1(applyTransmission(single, le, k, mu)[0]) ==
            Approx(cure::fppConversionAtDepth(1.7, 2 * le, k, mu)).epsilon(1e-14));
}

TEST_CASE("DLP: targets of Eq. 11-12", "[cure]") {
    std::vector<double> target = objectivePhotopolymerisation({1, 0, 1}, 0.95, 5.5);
    REQUIRE(target[0] == Approx(std::log(0.05)).epsilon(1e-15));
    REQUIRE(target[1] == 5.5);
    REQUIRE(target[2] == target[0]);
}

TEST_CASE("DLP: exposure bounds follow Eq. 10 across skipped layers", "[cure]") {
    DlpColumnProblem p = seedResin(10.0);
    const double ec = GEL / p.rateConstant, x = p.attenuation * p.layerThickness;
    std::vector<double> lower, upper;
    // Void layer 0, solid 1-4; layers 1 and 2 left unexposed: layer 3 bonds through 3 elements
    // down to the run's bottom surface, layer 4 through 1 to layer 3.
    REQUIRE(exposureBounds({0, 0, 0, 1, 1}, {0, 1, 1, 1, 1}, p, lower, upper));
    REQUIRE(lower[0] == 0.0);
    REQUIRE(lower[1] == 0.0);
    REQUIRE(lower[2] == 0.0);
    REQUIRE(lower[3] == Approx(ec * std::exp(3 * x)).epsilon(1e-14));
    REQUIRE(lower[4] == Approx(ec * std::exp(x)).epsilon(1e-14));
    REQUIRE(upper[3] == 10.0);
    REQUIRE(upper[1] == 0.0);
    p.maxDose = ec * std::exp(2.5 * x);  // enough for n_z = 1, 2 but not 3
    REQUIRE_FALSE(exposureBounds({0, 0, 0, 1, 1}, {0, 1, 1, 1, 1}, p, lower, upper));
    REQUIRE(exposureBounds({0, 0, 1, 1, 1}, {0, 1, 1, 1, 1}, p, lower, upper));
    REQUIRE_THROWS_WITH(exposureBounds({1, 0, 0, 1, 1}, {0, 1, 1, 1, 1}, p, lower, upper),
                        Catch::Contains("outside the part"));
}

TEST_CASE("DLP: with inactive bounds the solve reaches T^-1 phi_obj", "[cure]") {
    // All 20 layers solid and exposed, d_max large: the constraints are inactive at the optimum
    // (interior doses 3.0 (1-a)/K = 0.724 > d_min = 0.701 mJ/mm^2), so F = 0 is reached at the
    // bidiagonal inverse d_p = -(phi_p - a phi_{p+1}) / K, d_top = -phi / K. Tolerance 1e-8
    // relative: the stopping rule (1e-12 per step) times the condition number (~250).
    DlpColumnProblem p = seedResin(100.0);
    const size_t n = 20;
    std::vector<uint8_t> solid(n, 1);
    DlpColumnResult r = optimiseColumnDosesForPattern(solid, solid, p);
    REQUIRE(r.converged);
    const double phi = std::log(0.05), a = std::exp(-p.attenuation * p.layerThickness);
    for (size_t k = 0; k + 1 < n; ++k)
        REQUIRE(r.dose[k] == Approx(-(phi - a * phi) / p.rateConstant).epsilon(1e-8));
    REQUIRE(r.dose[n - 1] == Approx(-phi / p.rateConstant).epsilon(1e-8));
    for (double c : r.conversion) REQUIRE(c == Approx(0.95).epsilon(1e-9));
    REQUIRE(r.objective < 1e-14);
}

TEST_CASE("DLP: a single layer gets its clamped closed-form dose", "[cure]") {
    // One node: phi = -K d, so d = -ln(1 - 0.95)/K = 5.673 mJ/mm^2 unless d_max is lower.
    DlpColumnResult free = optimiseColumnDoses({1}, seedResin(10.0));
    REQUIRE(free.dose[0] == Approx(-std::log(0.05) / 0.528080236).epsilon(1e-9));
    DlpColumnResult capped = optimiseColumnDoses({1}, seedResin(1.3));  // Opt 2: 130 mJ/cm^2
    REQUIRE(capped.dose[0] == 1.3);
    REQUIRE(capped.conversion[0] == Approx(-std::expm1(-0.528080236 * 1.3)).epsilon(1e-14));
}

TEST_CASE("DLP: the constrained solve satisfies the KKT conditions", "[cure]") {
    // 10 void layers under 30 solid ones, all exposed, d_max 130 mJ/cm^2, penalty 5.5: bounds are
    // active. At the optimum of this convex problem the gradient vanishes on free doses, is <= 0
    // at the upper bound and >= 0 at the lower bound. Tolerance 1e-6 of the initial gradient scale.
    DlpColumnProblem p = seedResin(1.3);
    std::vector<uint8_t> solid(40, 1);
    for (int k = 0; k < 10; ++k) solid[k] = 0;
    DlpColumnResult r = optimiseColumnDosesForPattern(solid, solid, p);
    REQUIRE(r.converged);
    std::vector<double> lower, upper;
    REQUIRE(exposureBounds(solid, solid, p, lower, upper));
    std::vector<double> target = objectivePhotopolymerisation(solid, p.targetConversion, p.penalty);
    std::vector<double> phi =
        applyTransmission(r.dose, p.layerThickness, p.rateConstant, p.attenuation);
    for (size_t k = 0; k < phi.size(); ++k) phi[k] -= target[k];
    std::vector<double> g =
        applyTransmissionTransposed(phi, p.layerThickness, p.rateConstant, p.attenuation);
    double scale = 0.0;
    for (double v : g) scale = std::max(scale, std::abs(v));
    const double tol = 1e-6 * std::max(scale, 1.0);
    int atUpper = 0, atLower = 0, free = 0;
    for (size_t k = 10; k < 40; ++k) {
        if (r.dose[k] >= upper[k]) {
            ++atUpper;
            REQUIRE(g[k] <= tol);
        } else if (r.dose[k] <= lower[k]) {
            ++atLower;
            REQUIRE(g[k] >= -tol);
        } else {
            ++free;
            REQUIRE(std::abs(g[k]) <= tol);
        }
    }
    for (size_t k = 0; k < 10; ++k) REQUIRE(r.dose[k] == 0.0);
    INFO("free " << free << ", at d_min " << atLower << ", at d_max " << atUpper);
    REQUIRE(atUpper + atLower > 0);  // the case really exercises the constraints
}

TEST_CASE("DLP: optimised overhang grows less than the uniform 78 mJ/cm^2 plan", "[cure]") {
    // 1 mm overhang (20 layers) over 1 mm of void, 1 mm of void above. Growth below the
    // down-facing surface = Jacobs depth of the accumulated dose at its bottom. Seed 001 Table 2:
    // non-optimised parts grew ~0.66 mm, optimised ones far less. Our 1-D search reduces the
    // growth and more so with a larger penalty a (the trend of Fig. 9); it does NOT reproduce the
    // paper's 0.08 mm (see the report), so only these trends are asserted.
    std::vector<uint8_t> solid(60, 0);
    for (int k = 20; k < 40; ++k) solid[k] = 1;
    const double dp = 0.365935872, ec = GEL / 0.528080236;
    auto growth = [&](const std::vector<double>& dose) {
        return cure::jacobsCureDepth(cure::accumulatedBottomDoses(dose, 0.05, dp)[20], ec, dp);
    };
    std::vector<double> uniform(60, 0.0);
    for (int k = 20; k < 40; ++k) uniform[k] = 0.78;
    const double uniformGrowth = growth(uniform);  // 0.77 mm

    double previousGrowth = 1e9;
    for (double penalty : {0.0, 1.0, 5.5, 10.0}) {
        DlpColumnProblem p = seedResin(2.6);  // Opt 1: 260 mJ/cm^2
        p.penalty = penalty;
        DlpColumnResult r = optimiseColumnDoses(solid, p);
        // Feasible: doses within their pattern's bounds, nothing exposed outside the part.
        std::vector<double> lower, upper;
        REQUIRE(exposureBounds(r.exposed, solid, p, lower, upper));
        for (size_t k = 0; k < 60; ++k) {
            REQUIRE(r.dose[k] >= lower[k]);
            REQUIRE(r.dose[k] <= upper[k]);
        }
        // Never worse than exposing every solid layer (the search's starting pattern).
        REQUIRE(r.objective <= optimiseColumnDosesForPattern(solid, solid, p).objective);
        double g = growth(r.dose);
        INFO("penalty " << penalty << ": growth " << g << " mm vs uniform " << uniformGrowth
                        << " mm");
        REQUIRE(g < uniformGrowth);
        REQUIRE(g <= previousGrowth + 1e-9);
        previousGrowth = g;
    }
}

TEST_CASE("DLP: bad problems give clear errors", "[cure]") {
    using Catch::Contains;
    REQUIRE_THROWS_WITH(optimiseColumnDoses({1, 1}, seedResin(0.5)),
                        Contains("below the bonding dose"));
    DlpColumnProblem p = seedResin(2.0);
    p.targetConversion = 1.0;
    REQUIRE_THROWS_WITH(optimiseColumnDoses({1}, p), Contains("target conversion"));
    p = seedResin(2.0);
    p.penalty = -1.0;
    REQUIRE_THROWS_WITH(optimiseColumnDoses({1}, p), Contains("penalty"));
    p = seedResin(2.0);
    p.layerThickness = 0.0;
    REQUIRE_THROWS_WITH(optimiseColumnDoses({1}, p), Contains("layer thickness"));
    REQUIRE_THROWS_WITH(optimiseColumnDosesForPattern({1, 1}, {1}, seedResin(2.0)),
                        Contains("length"));
}
