// Mie invariants and closed-form limits: Rayleigh limit, optical theorem, the integral of the
// phase intensity over the sphere, stability across x = 0.01 .. 10^4, and bad input.

#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/optics/mie.h"
#include "vpsim/optics/phase_table.h"

using namespace vpsim::optics;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {
constexpr double PI = 3.14159265358979323846;
constexpr double SEED_QSCA = 2.317144881;  // mpmath, see "independent 60-digit computation"
}  // namespace

TEST_CASE("Mie reduces to Rayleigh scattering for x = 0.01", "[mie]") {
    // Closed forms (BH Eq. 5.8, 5.11, m = n - ik so the absorbing Im part enters with a minus):
    //   Qsca = 8/3 x^4 |(m^2-1)/(m^2+2)|^2, Qabs = -4 x Im((m^2-1)/(m^2+2)), Qback = 1.5 Qsca,
    //   g -> 0. Corrections are O(x^2) = 1e-4 relative, so the tolerance is 1e-3.
    const double x = 0.01;
    for (Complex m :
         {Complex(1.5, 0.0), Complex(1.33, -0.01), Complex(1.75, -0.5), Complex(0.75, 0.0)}) {
        INFO("m = " << formatRefractiveIndex(m));
        const Complex polar = (m * m - 1.0) / (m * m + 2.0);
        MieEfficiencies e = mieEfficiencies(mieCoefficients(m, x));
        const double qsca = 8.0 / 3.0 * std::pow(x, 4) * std::norm(polar);
        CHECK_THAT(e.qsca, WithinRel(qsca, 1e-3));
        CHECK_THAT(e.qback, WithinRel(1.5 * qsca, 1e-3));
        CHECK(std::fabs(e.g) < 1e-3);
        if (m.imag() < 0.0)
            CHECK_THAT(e.qabs, WithinRel(-4.0 * x * polar.imag(), 1e-3));
        else
            CHECK(std::fabs(e.qabs) < 1e-12 * e.qsca + 1e-20);
    }
}

TEST_CASE("Optical theorem: Qext = 4/x^2 Re S(0) and S1(0) = S2(0), S1(180) = -S2(180)", "[mie]") {
    // Exact identities; rounding only, tolerance 1e-12 relative.
    for (double x : {0.01, 0.5, 7.3, 56.0, 850.0}) {
        for (Complex m : {Complex(1.2, 0.0), Complex(1.5, -0.1), Complex(3.0, -2.0)}) {
            INFO("x = " << x << " m = " << formatRefractiveIndex(m));
            MieCoefficients c = mieCoefficients(m, x);
            MieEfficiencies e = mieEfficiencies(c);
            MieAmplitudes forward = mieAmplitudes(c, 1.0), backward = mieAmplitudes(c, -1.0);
            CHECK_THAT(4.0 / (x * x) * forward.s1.real(), WithinRel(e.qext, 1e-12));
            CHECK(std::abs(forward.s1 - forward.s2) <= 1e-12 * std::abs(forward.s1));
            CHECK(std::abs(backward.s1 + backward.s2) <= 1e-10 * std::abs(forward.s1));
            CHECK_THAT(4.0 * std::norm(backward.s1) / (x * x), WithinRel(e.qback, 1e-10));
            CHECK(e.qabs >= -1e-12 * e.qext);  // energy: a sphere cannot emit
        }
    }
}

TEST_CASE("Integral of K over the sphere equals pi x^2 Qsca and its mean cosine equals g",
          "[mie]") {
    // Two independent routes: Qsca and g from sums over the coefficients, the integrals from
    // S1, S2 on 0.1-degree (or finer) panels. Tolerance 1e-6 relative (the quadrature is of
    // high order; the requirement is 1e-4).
    for (double x : {0.01, 1.0, 10.0, 56.2, 300.0}) {
        for (Complex m : {Complex(1.2069, 0.0), Complex(1.5, -0.1), Complex(10.0, -10.0)}) {
            INFO("x = " << x << " m = " << formatRefractiveIndex(m));
            MieCoefficients c = mieCoefficients(m, x);
            MieEfficiencies e = mieEfficiencies(c);
            PhaseTable t = miePhaseTable(c);
            CHECK_THAT(t.integral, WithinRel(PI * x * x * e.qsca, 1e-6));
            CHECK_THAT(t.meanCosine, WithinAbs(e.g, 1e-6));
        }
    }
}

TEST_CASE("Integral of K equals pi x^2 Qsca at x = 10^4", "[mie][slow]") {
    // Same invariant at the top of the supported range (about 8e8 term evaluations).
    const double x = 1e4;
    MieCoefficients c = mieCoefficients({1.33, -1e-5}, x);
    MieEfficiencies e = mieEfficiencies(c);
    PhaseTable t = miePhaseTable(c);
    CHECK_THAT(t.integral, WithinRel(PI * x * x * e.qsca, 1e-4));
    CHECK_THAT(t.meanCosine, WithinAbs(e.g, 1e-4));
}

TEST_CASE("Mie is stable and physical from x = 0.01 to 10^4 for strongly absorbing, large |m|x",
          "[mie]") {
    // |m|x up to 1.4e5: the Lentz-seeded downward recurrence must give finite, physical values
    // and the large-x extinction limit Qext -> 2 (van de Hulst's extinction paradox; the edge
    // correction is ~2 x^(-2/3) = 0.004 at x = 1e4, tolerance 0.01).
    for (Complex m :
         {Complex(1.01, 0.0), Complex(1.75, 0.0), Complex(10.0, -10.0), Complex(1.5, -5.0)}) {
        for (double x = 0.01; x <= 1.0001e4; x *= 10.0) {
            INFO("x = " << x << " m = " << formatRefractiveIndex(m));
            MieEfficiencies e = mieEfficiencies(mieCoefficients(m, x));
            CHECK(std::isfinite(e.qext));
            CHECK(e.qsca > 0.0);
            CHECK(e.qsca <= e.qext * (1.0 + 1e-10));
            CHECK(e.g > -1.0);
            CHECK(e.g < 1.0);
            // The limit needs the phase shift rho = 2x|m-1| >> 1 too (not so for m = 1.01).
            if (x > 9e3 && x * std::abs(m - 1.0) > 1000.0) CHECK_THAT(e.qext, WithinAbs(2.0, 0.01));
        }
    }
}

TEST_CASE("Mie agrees with an independent 60-digit computation", "[mie]") {
    // Reference values computed for this test with mpmath at 60 significant digits by a different
    // algorithm (upward Riccati-Bessel recurrences for psi_n(x), psi_n(mx), chi_n(x), no
    // logarithmic derivatives), printed to 10 digits: a cross-check, not a publication.
    // m = 1.01, x = 1e4 (rho = 200, where anomalous diffraction is still off by 2 %) and the
    // seed-000 sphere m = 1.75/1.45, x = 2 pi 2.5 um 1.45 / 405 nm.
    CHECK_THAT(mieEfficiencies(mieCoefficients({1.01, 0.0}, 1e4)).qext,
               WithinRel(2.021983175, 1e-9));
    const double xSeed = 2.0 * PI * 2.5 * 1.45 / 0.405;
    CHECK_THAT(mieEfficiencies(mieCoefficients({1.75 / 1.45, 0.0}, xSeed)).qsca,
               WithinRel(SEED_QSCA, 1e-9));
}

TEST_CASE("Wiscombe's term count", "[mie]") {
    // Wiscombe 1980: x + 4 x^(1/3) + 1 (x <= 8), x + 4.05 x^(1/3) + 2 above (up to 4200).
    CHECK(wiscombeTermCount(1.0) == 6);
    CHECK(wiscombeTermCount(10.0) == 20);
    CHECK(wiscombeTermCount(100.0) == 120);
    CHECK(wiscombeTermCount(1000.0) == 1042);
}

TEST_CASE("Refractive index strings follow m = n - ik", "[mie]") {
    CHECK(parseRefractiveIndex("1.5") == Complex(1.5, 0.0));
    CHECK(parseRefractiveIndex("1.5-0.1i") == Complex(1.5, -0.1));
    CHECK(parseRefractiveIndex(" 1.5 - 0.1j ") == Complex(1.5, -0.1));
    CHECK(parseRefractiveIndex("1.5-i0.1") == Complex(1.5, -0.1));
    CHECK(parseRefractiveIndex("1e0-1e-3i") == Complex(1.0, -1e-3));
    CHECK(parseRefractiveIndex("1.5+0i") == Complex(1.5, 0.0));
    // A positive imaginary part would be a gain medium in this convention: refused with advice.
    CHECK_THROWS_WITH(parseRefractiveIndex("1.5+0.1i", "--m"), Contains("negative imaginary"));
    for (const char* bad :
         {"", "abc", "1.5-0.1", "1.5-0.1k", "1.5--0.1i", "-1.5", "0", "1.5i", "nan"}) {
        INFO("'" << bad << "'");
        CHECK_THROWS_AS(parseRefractiveIndex(bad), vpsim::InputError);
    }
    CHECK(formatRefractiveIndex({1.5, -0.1}) == "1.5-0.1i");
}

TEST_CASE("Mie refuses impossible inputs", "[mie]") {
    CHECK_THROWS_AS(mieCoefficients({1.5, 0.0}, 0.0), vpsim::InputError);
    CHECK_THROWS_AS(mieCoefficients({1.5, 0.0}, -1.0), vpsim::InputError);
    CHECK_THROWS_AS(mieCoefficients({1.5, 0.0}, 3e4), vpsim::InputError);
    CHECK_THROWS_AS(mieCoefficients({1.5, 0.1}, 1.0), vpsim::InputError);
    CHECK_THROWS_AS(mieCoefficients({0.0, 0.0}, 1.0), vpsim::InputError);
    CHECK_THROWS_AS(mieCoefficients({std::nan(""), 0.0}, 1.0), vpsim::InputError);
}
