// Cure laws: Jacobs threshold and FPP conversion (seed 001 Eq. 1-2), their equivalence, and the
// CureLaw classes.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"
#include "vpsim/cure/fpp_law.h"
#include "vpsim/cure/threshold_law.h"

using namespace vpsim;
using namespace vpsim::cure;

TEST_CASE(
    "FPP cure depth (Eq. 2) equals the Jacobs working curve with Dp = 1/mu, Ec = ln(1/(1-Phi_c))/K",
    "[cure]") {
    // Both are closed forms of the same gel condition; they may differ only by rounding (1e-12
    // rel).
    for (double k : {0.05, 0.528, 3.0})            // mm^2/mJ
        for (double mu : {0.5, 2.73, 40.0})        // 1/mm
            for (double gel : {0.05, 0.276, 0.9})  // Phi_c
                for (double factor : {1.001, 2.0, 17.0, 1e4}) {
                    double ec = fppGelDose(k, gel);
                    double dose = factor * ec;
                    double zf = fppCureDepth(dose, k, mu, gel);
                    double cd = jacobsCureDepth(dose, ec, 1.0 / mu);
                    REQUIRE(zf == Approx(cd).epsilon(1e-12));
                    // The gel condition itself: Phi(Zf, d) = Phi_c (Eq. 1 evaluated at Eq. 2).
                    REQUIRE(fppConversionAtDepth(dose, zf, k, mu) == Approx(gel).epsilon(1e-12));
                }
}

TEST_CASE("FPP gel dose of the seed 001 resin gel point", "[cure]") {
    // Hand value: ln(1/(1-0.276)) = -ln(0.724) = 0.3229638865964207 (computed independently).
    REQUIRE(fppGelDose(1.0, 0.276) == Approx(0.3229638865964207).epsilon(1e-15));
    REQUIRE(fppGelDose(0.5, 0.276) == Approx(2.0 * 0.3229638865964207).epsilon(1e-15));
    REQUIRE(fppRateConstantFromCriticalDose(fppGelDose(0.37, 0.4), 0.4) ==
            Approx(0.37).epsilon(1e-15));
}

TEST_CASE("Conversion and cure depth are monotonic in dose and depth", "[cure]") {
    const double k = 0.528, mu = 2.73, gel = 0.276;
    double previousPhi = -1.0, previousDepth = -1.0;
    // Up to K E ~ 16, where 1 - Phi = 1e-7 is still resolved in double.
    for (double dose = 0.01; dose < 30.0; dose *= 1.3) {
        double phi = fppConversion(dose, k);
        REQUIRE(phi > previousPhi);
        REQUIRE(phi >= 0.0);
        REQUIRE(phi < 1.0);
        double depth = fppCureDepth(dose, k, mu, gel);
        REQUIRE(depth >= previousDepth);
        previousPhi = phi;
        previousDepth = depth;
    }
    double previous = 2.0;
    for (double z = 0.0; z < 3.0; z += 0.1) {
        double phi = fppConversionAtDepth(10.0, z, k, mu);
        REQUIRE(phi < previous);
        previous = phi;
    }
    // Below the critical dose nothing cures.
    REQUIRE(jacobsCureDepth(0.5, 0.6, 0.37) == 0.0);
    REQUIRE(fppCureDepth(0.99 * fppGelDose(k, gel), k, mu, gel) == 0.0);
    // Small-dose limit: Phi ~ K E to first order (relative error ~ K E / 2 = 5e-9 here).
    REQUIRE(fppConversion(1e-8, k) == Approx(k * 1e-8).epsilon(1e-8));
}

TEST_CASE("Cure laws: iso-level, conversion and cure depth", "[cure]") {
    FppLaw fpp(0.528, 0.276, 0.366);
    REQUIRE(fpp.name() == "fpp");
    REQUIRE(fpp.criticalDose() == Approx(0.3229638865964207 / 0.528).epsilon(1e-14));
    // At the iso-level the conversion is the gel point.
    REQUIRE(fpp.conversion(fpp.criticalDose()) == Approx(0.276).epsilon(1e-13));
    REQUIRE(fpp.isCured(fpp.criticalDose()));
    REQUIRE_FALSE(fpp.isCured(std::nextafter(fpp.criticalDose(), 0.0)));
    REQUIRE(fpp.cureDepth(10.0 * fpp.criticalDose()) ==
            Approx(0.366 * std::log(10.0)).epsilon(1e-14));

    ThresholdLaw threshold(0.6, 0.366);
    REQUIRE(threshold.name() == "threshold");
    REQUIRE(threshold.conversion(0.5999) == 0.0);
    REQUIRE(threshold.conversion(0.6) == 1.0);
    REQUIRE(threshold.cureDepth(0.6 * std::exp(2.0)) == Approx(0.732).epsilon(1e-14));

    ThresholdLaw noDepth(0.6);
    REQUIRE_FALSE(noDepth.hasPenetrationDepth());
    REQUIRE_THROWS_AS(noDepth.cureDepth(1.0), InputError);
}

TEST_CASE("Cure laws refuse impossible parameters", "[cure]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    REQUIRE_THROWS_AS(ThresholdLaw(0.0), InputError);
    REQUIRE_THROWS_AS(ThresholdLaw(-1.0, 0.3), InputError);
    REQUIRE_THROWS_AS(ThresholdLaw(nan), InputError);
    REQUIRE_THROWS_AS(ThresholdLaw(1.0, -0.3), InputError);
    REQUIRE_THROWS_AS(FppLaw(0.0, 0.276), InputError);
    REQUIRE_THROWS_AS(FppLaw(0.5, 0.0), InputError);
    REQUIRE_THROWS_AS(FppLaw(0.5, 1.0), InputError);
    REQUIRE_THROWS_AS(jacobsCureDepth(1.0, 0.5, 0.0), InputError);
    REQUIRE_THROWS_AS(fppCureDepth(1.0, 0.5, 0.0, 0.276), InputError);
    REQUIRE_THROWS_WITH(FppLaw(0.5, 1.5), Catch::Contains("gel point"));
}
