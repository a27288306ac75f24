// Whole-array cure: masks and conversion fields against the scalar model, serial and threaded.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "vpsim/cure/cure_field.h"
#include "vpsim/cure/fpp_law.h"
#include "vpsim/cure/threshold_law.h"

using namespace vpsim::cure;

TEST_CASE("Cure mask and conversion field agree with the scalar model", "[cure]") {
    FppLaw fpp(0.528, 0.276);
    const float level = float(fpp.criticalDose());
    // Edge cases: exactly at the iso-level, just below, zero, negative, NaN, huge.
    std::vector<float> dose = {
        level, std::nextafter(level, 0.0f), 0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(),
        1e30f};
    std::vector<uint8_t> mask = cureMask(fpp, dose);
    REQUIRE(mask == std::vector<uint8_t>{1, 0, 0, 0, 0, 1});
    std::vector<float> phi = conversionField(fpp, dose);
    REQUIRE(phi[0] == Approx(0.276).epsilon(1e-6));  // float iso-level rounding: ~1e-7 relative
    REQUIRE(phi[2] == 0.0f);
    REQUIRE(phi[3] == 0.0f);
    REQUIRE(phi[5] == 1.0f);

    ThresholdLaw threshold(0.61);
    REQUIRE(conversionField(threshold, std::vector<float>{0.6f, 0.61f, 2.0f}) ==
            std::vector<float>{0, 1, 1});
}

TEST_CASE("Threaded cure of a large array matches the per-voxel model", "[cure]") {
    // 3 Mi voxels spans several 1 Mi chunks, so the TBB path runs. Fixed seed.
    const size_t count = size_t(3) << 20;
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> uniform(0.0f, 2.0f);
    std::vector<float> dose(count);
    for (float& d : dose) d = uniform(rng);
    FppLaw model(0.528, 0.276);
    std::vector<uint8_t> mask = cureMask(model, dose);
    std::vector<float> phi = conversionField(model, dose);
    size_t expectedCured = 0, mismatches = 0;
    double worstPhiError = 0.0;
    for (size_t i = 0; i < count; ++i) {
        bool cured = dose[i] >= float(model.criticalDose());
        expectedCured += cured;
        mismatches += (mask[i] != uint8_t(cured));
        worstPhiError = std::max(worstPhiError, std::abs(phi[i] - model.conversion(dose[i])));
    }
    REQUIRE(mismatches == 0);
    REQUIRE(countCured(model, dose.data(), count) == expectedCured);
    // Float evaluation of 1 - exp(-K E): a few float ulps of values below 1 (tolerance 1e-6).
    REQUIRE(worstPhiError < 1e-6);
    // Uniform doses on [0, 2]: the cured fraction is 1 - Ec/2 within binomial noise
    // (sd ~ 0.5/sqrt(3e6) = 3e-4; tolerance 2e-3).
    REQUIRE(double(expectedCured) / count == Approx(1.0 - model.criticalDose() / 2.0).margin(2e-3));
}
