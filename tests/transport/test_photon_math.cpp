// The photon step's own exponential deviate and azimuth (shaders/include/photon_step.glsl), which
// replace log, sin and cos in the step loop: checked against libm in double precision.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>

#include "transport/photon_params.h"

namespace vpsim::glsl {
namespace {
#include "rng.glsl"
// Hooks photon_step.glsl needs; these tests trace no photon.
float photonPhaseTable(int) {
    return 0;
}
void photonAddBin(uint, uint, uint64_t) {}
void photonAddVoxel(uint, uint64_t) {}
uint photonEstimator(const PhotonParams& p) {
    return p.estimator & 255u;
}
#include "photon_step.glsl"
}  // namespace
}  // namespace vpsim::glsl

namespace {

/// The random words whose top 24 bits are m (the low 8 bits do not matter).
uint32_t wordOf(uint32_t m) {
    return (m << 8) | 0x5Au;
}

}  // namespace

TEST_CASE("photonExponential is -ln(u) of rngUniform's u for every 24-bit value", "[transport]") {
    double worstRelative = 0, worstAbsolute = 0;
    uint64_t negative = 0;
    for (uint32_t m = 0; m < (1u << 24); ++m) {
        const double u = (m + 1.0) / 16777216.0;  // what rngUniform returns for these bits
        const double exact = -std::log(u);
        const double got = vpsim::glsl::photonExponential(wordOf(m));
        negative += got < 0.0;
        worstAbsolute = std::max(worstAbsolute, std::abs(got - exact));
        if (exact > 0) worstRelative = std::max(worstRelative, std::abs(got - exact) / exact);
    }
    INFO("worst relative error " << worstRelative << ", absolute " << worstAbsolute);
    CHECK(negative == 0);
    CHECK(vpsim::glsl::photonExponential(wordOf((1u << 24) - 1u)) == 0.0f);  // u = 1
    CHECK(worstRelative < 4e-7);  // a few float roundings, also as u -> 1
    CHECK(worstAbsolute < 4e-6);  // at -ln(2^-24) = 16.6
}

TEST_CASE("photonAzimuth is a unit vector at the angle its bits encode", "[transport]") {
    // Quadrant q (top 2 bits) and 22-bit offset j: the angle q pi/2 + (j + 1/2 - 2^21) pi/2^23.
    double worst = 0, worstNorm = 0;
    uint64_t checked = 0;
    for (uint32_t q = 0; q < 4; ++q)
        for (uint32_t j = 0; j < (1u << 22); j += 7) {
            const uint32_t bits = (q << 30) | (j << 8) | 0xA5u;
            const double angle = q * M_PI / 2 + (j + 0.5 - 2097152.0) * (M_PI / 2 / 4194304.0);
            const vpsim::glsl::vec2 a = vpsim::glsl::photonAzimuth(bits);
            worst =
                std::max({worst, std::abs(a.x - std::cos(angle)), std::abs(a.y - std::sin(angle))});
            worstNorm = std::max(worstNorm, std::abs(double(a.x) * a.x + double(a.y) * a.y - 1.0));
            ++checked;
        }
    INFO(checked << " angles: worst component error " << worst << ", worst |a|^2 - 1 "
                 << worstNorm);
    CHECK(worst < 2e-7);
    CHECK(worstNorm < 5e-7);
}

TEST_CASE("photonAzimuth covers the circle uniformly", "[transport]") {
    // 2^20 words spread over all 32 bits: the mean of (cos, sin) is 0 and each octant holds 1/8.
    double sx = 0, sy = 0;
    uint64_t octants[8] = {};
    const uint32_t n = 1u << 20;
    for (uint32_t i = 0; i < n; ++i) {
        const vpsim::glsl::vec2 a = vpsim::glsl::photonAzimuth(i * 4096u + 2048u);
        sx += a.x;
        sy += a.y;
        double phi = std::atan2(double(a.y), double(a.x));
        if (phi < 0) phi += 2 * M_PI;
        ++octants[std::min(7, int(phi / (M_PI / 4)))];
    }
    CHECK(std::abs(sx / n) < 1e-5);
    CHECK(std::abs(sy / n) < 1e-5);
    for (uint64_t o : octants) CHECK(std::abs(double(o) / n - 0.125) < 1e-4);
}

TEST_CASE("photonExp is e^x for x <= 0 to float precision", "[transport]") {
    // The control variates (photon_control.glsl) subtract expectations made of photonExp: their
    // bias is its relative error times a few, so it must be float-exact, down to -87 where it
    // flushes to 0.
    double worst = 0;
    for (int i = 0; i <= 2000000; ++i) {
        const float x = float(-87.0 * i / 2000000.0);
        const double exact = std::exp(double(x));
        worst = std::max(worst, std::abs(double(vpsim::glsl::photonExp(x)) - exact) / exact);
    }
    INFO("worst relative error " << worst);
    CHECK(worst < 3e-7);
    CHECK(vpsim::glsl::photonExp(0.0f) == 1.0f);
    CHECK(vpsim::glsl::photonExp(-88.0f) == 0.0f);
    CHECK(vpsim::glsl::photonExp(-1e30f) == 0.0f);
}
