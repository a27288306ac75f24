// Phase tables and slurry optics: normalisation, mean cosine of the tabulated and sampled
// inverse CDF, the seed-000 slurry numbers, and the log-normal size distribution.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "vpsim/core/error.h"
#include "vpsim/optics/phase_table.h"
#include "vpsim/optics/slurry.h"

using namespace vpsim::optics;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {
constexpr double PI = 3.14159265358979323846;

/// Seed 000 Section II-C / tests/data/reference/seed000_slurry_case.json, in mm.
SlurrySpec seedSlurry() {
    SlurrySpec s;
    s.wavelength = 405e-6;
    s.resinIndex = 1.45;
    s.resinPenetrationDepth = 0.119;
    s.particleIndex = {1.75, 0.0};
    s.radius = 2.5e-3;
    s.volumeFraction = 0.5;
    return s;
}

/// Mean of cos(theta) over n jittered-stratified samples u = (i + r_i)/n of the table, sampled as
/// the Monte Carlo does (linear interpolation in u). Fixed seed.
double stratifiedSampleMean(const PhaseTable& t, int n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += t.sampleCosine((i + uniform(rng)) / n);
    return sum / n;
}
}  // namespace

TEST_CASE("Seed-000 slurry: x, m, Qs, g and mean free paths", "[phase]") {
    // Inputs from seed 000 Sec. II-C (lambda 405 nm, n_m 1.45, n_s 1.75, R 2.5 um, Phi 0.5,
    // Dp0 119 um). The seed does not print Qs or lambda_s, so they are checked against closed
    // forms: x and m by definition, lambda_s by Eq. 8, mua by Eq. 10 read as 1/Dp0, and Qs
    // against van de Hulst's anomalous-diffraction Q = 2 - 4/rho sin rho + 4/rho^2 (1 - cos rho),
    // rho = 2x(m-1), which lacks the edge term ~2 x^(-2/3) = 0.13: tolerance 10 %.
    SlurryOptics o = computeSlurryOptics(seedSlurry());
    CHECK_THAT(o.x, WithinRel(2.0 * PI * 2.5e-3 * 1.45 / 405e-6, 1e-12));  // 56.238
    CHECK_THAT(o.m.real(), WithinRel(1.75 / 1.45, 1e-12));
    CHECK(o.m.imag() == 0.0);
    const double rho = 2.0 * o.x * (o.m.real() - 1.0);
    const double ada = 2.0 - 4.0 / rho * std::sin(rho) + 4.0 / (rho * rho) * (1.0 - std::cos(rho));
    CHECK_THAT(o.efficiencies.qsca, WithinRel(ada, 0.10));
    CHECK_THAT(o.efficiencies.qext, WithinRel(o.efficiencies.qsca, 1e-12));  // non-absorbing
    CHECK(o.efficiencies.g > 0.85);  // strongly forward scattering (x >> 1, m near 1)
    CHECK(o.efficiencies.g < 0.98);
    const double lambdaS = 4.0 * 2.5e-3 / (3.0 * 0.5 * o.efficiencies.qsca);  // Eq. 8, mm
    CHECK_THAT(o.scatteringMeanFreePath, WithinRel(lambdaS, 1e-12));
    CHECK_THAT(o.transportMeanFreePath, WithinRel(lambdaS / (1.0 - o.efficiencies.g), 1e-12));
    CHECK_THAT(o.medium.mus, WithinRel(1.0 / lambdaS, 1e-12));
    CHECK_THAT(o.medium.mua, WithinRel(1.0 / 0.119, 1e-12));
    CHECK(o.medium.phase == PhaseModel::Tabulated);
    CHECK(o.medium.refractiveIndex == 1.45);
    CHECK(o.medium.inverseCdf.size() == static_cast<size_t>(DEFAULT_PHASE_TABLE_SIZE));
}

TEST_CASE("Seed-000 phase table: normalisation and mean cosine (tabulated and sampled)",
          "[phase]") {
    // Requirement 1e-4 for each. The sampled mean uses 2e6 jittered-stratified samples (its
    // statistical error is far below 1e-5), i.e. it measures the interpolation the MC uses.
    SlurryOptics o = computeSlurryOptics(seedSlurry());
    const PhaseTable& t = o.phase;
    CHECK_THAT(t.integral, WithinRel(PI * o.x * o.x * o.efficiencies.qsca, 1e-4));
    CHECK_THAT(t.meanCosine, WithinAbs(o.efficiencies.g, 1e-4));
    CHECK_THAT(t.tableMeanCosine(), WithinAbs(o.efficiencies.g, 1e-4));
    CHECK_THAT(stratifiedSampleMean(t, 2000000, 12345), WithinAbs(o.efficiencies.g, 1e-4));
    // Plain random sampling: the standard error is sqrt(var)/sqrt(N); tolerance 5 sigma.
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const int n = 1000000;
    double sum = 0.0, sumSq = 0.0;
    for (int i = 0; i < n; ++i) {
        double mu = t.sampleCosine(uniform(rng));
        sum += mu;
        sumSq += mu * mu;
    }
    const double mean = sum / n, sigma = std::sqrt((sumSq / n - mean * mean) / n);
    CHECK_THAT(mean, WithinAbs(o.efficiencies.g, 5.0 * sigma));
}

TEST_CASE("Inverse CDF runs from +1 to -1, is monotone, and inverts the CDF", "[phase]") {
    SlurryOptics o = computeSlurryOptics(seedSlurry());
    const PhaseTable& t = o.phase;
    REQUIRE(t.inverseCdf.front() == 1.0f);
    REQUIRE(t.inverseCdf.back() == -1.0f);
    for (size_t i = 1; i < t.inverseCdf.size(); ++i)
        REQUIRE(t.inverseCdf[i] <= t.inverseCdf[i - 1]);
    // CDF(theta(u)) = u: the theta of entry i maps back to u_i within one panel's CDF step.
    const size_t n = t.inverseCdf.size();
    for (size_t i = 1; i + 1 < n; i += 97) {
        const double u = static_cast<double>(i) / (n - 1);
        const double theta = std::acos(std::clamp(double(t.inverseCdf[i]), -1.0, 1.0));
        CHECK_THAT(t.cdfAt(theta), WithinAbs(u, 2e-4));  // float cos near theta=0 costs ~1e-4
    }
    // The panels are at most 0.1 degree wide.
    for (size_t i = 1; i < t.thetaEdges.size(); ++i)
        REQUIRE(t.thetaEdges[i] - t.thetaEdges[i - 1] <= MAX_PHASE_PANEL_WIDTH * (1 + 1e-12));
}

TEST_CASE("Isotropic K gives the analytic uniform-in-cos table", "[phase]") {
    // K = const: CDF(theta) = (1 - cos theta)/2, inverse cos = 1 - 2u, mean cosine 0. Tolerance
    // 1e-6 (float storage).
    ThetaQuadrature q = makeThetaQuadrature();
    PhaseTable t = buildPhaseTable(q, std::vector<double>(q.nodeMu.size(), 3.0), 1001);
    CHECK_THAT(t.integral, WithinRel(3.0 * 4.0 * PI, 1e-12));
    CHECK_THAT(t.meanCosine, WithinAbs(0.0, 1e-12));
    for (int i = 0; i < 1001; i += 50)
        CHECK_THAT(t.inverseCdf[i], WithinAbs(1.0 - 2.0 * i / 1000.0, 1e-6));
    CHECK_THAT(t.cdfAt(PI / 3.0), WithinAbs(0.25, 1e-6));
    CHECK_THROWS_AS(buildPhaseTable(q, std::vector<double>(3, 1.0)), vpsim::InputError);
    CHECK_THROWS_AS(buildPhaseTable(q, std::vector<double>(q.nodeMu.size(), 0.0)),
                    vpsim::InputError);
    CHECK_THROWS_AS(buildPhaseTable(q, std::vector<double>(q.nodeMu.size(), 1.0), 1),
                    vpsim::InputError);
}

TEST_CASE("Log-normal slurry: averages reduce correctly and the table stays normalised",
          "[phase]") {
    SlurrySpec mono = seedSlurry();
    SlurrySpec poly = mono;
    poly.size.kind = SizeDistribution::Kind::LogNormal;
    poly.size.sigmaG = 1.3;
    SlurryOptics p = computeSlurryOptics(poly);
    // Normalisation of the averaged K: integral = k^2 <Csca> (dC/dOmega = K/k^2), tolerance 1e-4.
    const double k = 2.0 * PI * 1.45 / 405e-6;
    CHECK_THAT(p.phase.integral, WithinRel(k * k * p.scatteringCrossSection, 1e-4));
    CHECK_THAT(p.phase.meanCosine, WithinAbs(p.efficiencies.g, 1e-4));
    CHECK_THAT(p.phase.tableMeanCosine(), WithinAbs(p.efficiencies.g, 1e-4));
    // Number density from <r^3> = rg^3 exp(4.5 ln^2 sigma_g) (closed form of the log-normal):
    // mus = Phi <Csca> / (4/3 pi <r^3>); the quadrature must reproduce it to 1e-4.
    const double r3 = std::pow(2.5e-3, 3) * std::exp(4.5 * std::pow(std::log(1.3), 2));
    CHECK_THAT(p.medium.mus,
               WithinRel(0.5 * p.scatteringCrossSection / (4.0 / 3.0 * PI * r3), 1e-4));
    // A width sigma_g -> 1 converges to the monodisperse result. Absorbing particles are used
    // because the narrow Mie resonances of a real m = 1.2 sphere make even a 0.1 % size spread
    // change Qsca by 0.25 %; with k = 0.01 (Im(m) x = 0.4) the resonances are damped and the
    // O(ln^2 sigma_g) = 1e-8 change is far below the 1e-5 tolerance.
    mono.particleIndex = {1.75, -0.01};
    SlurrySpec narrow = mono;
    narrow.size.kind = SizeDistribution::Kind::LogNormal;
    narrow.size.sigmaG = 1.0001;
    SlurryOptics n = computeSlurryOptics(narrow), m = computeSlurryOptics(mono);
    CHECK_THAT(n.medium.mus, WithinRel(m.medium.mus, 1e-5));
    CHECK_THAT(n.medium.mua, WithinRel(m.medium.mua, 1e-5));
    CHECK_THAT(n.efficiencies.g, WithinAbs(m.efficiencies.g, 1e-5));
}

TEST_CASE(
    "Absorption: pure-resin reading of seed Eq. 10, optional resin-fraction scaling, absorbing "
    "particles",
    "[phase]") {
    SlurrySpec s = seedSlurry();
    s.absorptionScaledByResinFraction = true;
    CHECK_THAT(computeSlurryOptics(s).medium.mua, WithinRel(0.5 / 0.119, 1e-12));
    // Absorbing particles add N <Cabs> = 3 Phi Qabs / (4 r) (monodisperse).
    SlurrySpec a = seedSlurry();
    a.particleIndex = {1.75, -0.01};
    SlurryOptics o = computeSlurryOptics(a);
    REQUIRE(o.efficiencies.qabs > 0.0);
    CHECK_THAT(o.medium.mua,
               WithinRel(1.0 / 0.119 + 3.0 * 0.5 * o.efficiencies.qabs / (4.0 * 2.5e-3), 1e-12));
}

TEST_CASE("Slurry refuses impossible values", "[phase]") {
    auto refuses = [](auto edit) {
        SlurrySpec s = seedSlurry();
        edit(s);
        CHECK_THROWS_AS(computeSlurryOptics(s), vpsim::InputError);
    };
    refuses([](SlurrySpec& s) { s.radius = -1e-3; });
    refuses([](SlurrySpec& s) { s.volumeFraction = 0.74; });
    refuses([](SlurrySpec& s) { s.volumeFraction = 0.0; });
    refuses([](SlurrySpec& s) { s.resinIndex = 0.0; });
    refuses([](SlurrySpec& s) { s.particleIndex = {-1.0, 0.0}; });
    refuses([](SlurrySpec& s) { s.particleIndex = {1.75, 0.1}; });
    refuses([](SlurrySpec& s) { s.wavelength = 0.0; });
    refuses([](SlurrySpec& s) { s.resinPenetrationDepth = 0.0; });
    refuses([](SlurrySpec& s) { s.radius = 10.0; });  // x = 2e5 is above the supported range
    refuses([](SlurrySpec& s) {
        s.size.kind = SizeDistribution::Kind::LogNormal;
        s.size.sigmaG = 0.5;
    });
}
