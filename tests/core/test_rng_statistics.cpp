#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "vpsim/core/rng.h"

using namespace vpsim;

// One million draws across 10,000 streams (as photons use them): the sample mean of U(0,1] has
// standard error sqrt(1/12/N) = 2.9e-4, so 5 standard errors is 1.5e-3; the variance 1/12 has
// standard error ~ sqrt(1/180/N) = 7.5e-5 -> tolerance 4e-4.
TEST_CASE("RNG uniform floats have the mean and variance of the unit interval", "[core][rng]") {
    const int streams = 10000, perStream = 100;
    double sum = 0, sumSq = 0;
    float lo = 1.0f, hi = 0.0f;
    for (int k = 0; k < streams; ++k) {
        Rng rng(7u, uint32_t(k));
        for (int i = 0; i < perStream; ++i) {
            float u = rng.uniform();
            sum += u;
            sumSq += double(u) * u;
            lo = std::min(lo, u);
            hi = std::max(hi, u);
        }
    }
    double n = double(streams) * perStream;
    double mean = sum / n, variance = sumSq / n - mean * mean;
    CHECK(std::abs(mean - 0.5) < 1.5e-3);
    CHECK(std::abs(variance - 1.0 / 12.0) < 4e-4);
    CHECK(lo > 0.0f);
    CHECK(hi <= 1.0f);
}

// Chi-square with 255 degrees of freedom: mean 255, sd 22.6; the 99.99% quantile is ~345.
// Checked on the first draw of consecutive streams (the weakest point of per-photon seeding) and
// on draws within one stream.
TEST_CASE("RNG passes chi-square uniformity across and within streams", "[core][rng]") {
    const int bins = 256, draws = 256 * 1000;
    auto chiSquare = [&](auto&& draw) {
        std::vector<int> counts(bins, 0);
        for (int i = 0; i < draws; ++i) counts[std::min(bins - 1, int(draw(i) * bins))]++;
        double expected = double(draws) / bins, chi = 0;
        for (int c : counts) chi += (c - expected) * (c - expected) / expected;
        return chi;
    };
    double across = chiSquare([](int i) { return Rng(12345u, uint32_t(i)).uniform(); });
    Rng single(99u, 0u);
    double within = chiSquare([&](int) { return single.uniform(); });
    CHECK(across < 345.0);
    CHECK(within < 345.0);
    CHECK(across > 170.0);  // 0.01% lower quantile: too-regular output is also a failure
    CHECK(within > 170.0);
}

TEST_CASE("RNG streams are reproducible and distinct", "[core][rng]") {
    auto a = rngStreamsCpu(1u, 0u, 64u, 8u, 0u);
    auto b = rngStreamsCpu(1u, 0u, 64u, 8u, 0u);
    auto c = rngStreamsCpu(2u, 0u, 64u, 8u, 0u);
    CHECK(a == b);
    CHECK(a != c);
    // Stream k of a batch starting at 10 equals stream 10+k of a batch starting at 0.
    auto shifted = rngStreamsCpu(1u, 10u, 4u, 8u, 0u);
    CHECK(std::equal(shifted.begin(), shifted.end(), a.begin() + 10 * 8));
    // Adjacent streams must not be correlated: compare first words bitwise (expected 16 of 32 bits
    // differ).
    double differing = 0;
    for (int k = 0; k + 1 < 64; ++k) differing += __builtin_popcount(a[k * 8] ^ a[(k + 1) * 8]);
    CHECK(differing / 63.0 == Approx(16.0).margin(2.0));
}
