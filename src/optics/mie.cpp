// Lorenz-Mie coefficients and efficiencies. See include/vpsim/optics/mie.h for the conventions.
//
// Internally the coefficients are computed in the Bohren & Huffman convention (m = n + ik,
// xi_n = psi_n - i chi_n) with mBH = conj(m), then conjugated, which gives the exp(+i w t)
// (Wiscombe) values for the user's m = n - ik. Formulas: BH Sec. 4.8 (coefficients through the
// logarithmic derivative D_n(mx)), as in Wiscombe, Appl. Opt. 19, 1505 (1980):
//   a_n = psi_n (D_n(mx)/m - D_n(x)) / [(D_n(mx)/m + n/x) xi_n - xi_{n-1}]
//   b_n = psi_n (m D_n(mx) - D_n(x)) / [(m D_n(mx) + n/x) xi_n - xi_{n-1}]
// where psi_{n-1} = (D_n(x) + n/x) psi_n was used to remove the cancellation in the numerators.

#include "vpsim/optics/mie.h"
#include "vpsim/core/text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "vpsim/core/error.h"

namespace vpsim::optics {
namespace {

/// a / b by Smith's algorithm: no overflow for large |b| and much cheaper than the library's
/// fully IEEE-checked complex division.
inline Complex divide(Complex a, Complex b) {
    const double br = b.real(), bi = b.imag();
    if (std::fabs(br) >= std::fabs(bi)) {
        const double r = bi / br, d = br + bi * r;
        return {(a.real() + a.imag() * r) / d, (a.imag() - a.real() * r) / d};
    }
    const double r = br / bi, d = br * r + bi;
    return {(a.real() * r + a.imag()) / d, (a.imag() * r - a.real()) / d};
}
inline double divide(double a, double b) {
    return a / b;
}
inline double magnitude(double v) {
    return std::fabs(v);
}
inline double magnitude(Complex v) {
    return std::abs(v);
}

/// Ratio psi_{N-1}(z)/psi_N(z) = J_{N-1/2}(z)/J_{N+1/2}(z) by the modified Lentz method
/// (Lentz 1976; Numerical Recipes 5.2). Terms a_k = (-1)^(k+1) (2N + 2k - 1)/z.
template <typename T>
T besselRatioLentz(int order, T z) {
    const double TINY = 1e-300;
    const double EPS = 1e-15;
    const T inverseZ = divide(T(1.0), z);
    auto term = [&](int k) {
        double sign = (k % 2 == 1) ? 1.0 : -1.0;
        return sign * (2.0 * order + 2.0 * k - 1.0) * inverseZ;
    };
    T f = term(1);
    if (magnitude(f) < TINY) f = TINY;
    T c = f, d = 0.0;
    for (int k = 2; k < 10000000; ++k) {
        const T ak = term(k);
        d = ak + d;
        if (magnitude(d) < TINY) d = TINY;
        c = ak + divide(T(1.0), c);
        if (magnitude(c) < TINY) c = TINY;
        d = divide(T(1.0), d);
        const T delta = c * d;
        f *= delta;
        if (magnitude(delta - 1.0) < EPS) return f;
    }
    throw Error("Mie: Lentz continued fraction did not converge for |z| = " +
                formatQuantity(magnitude(z)));
}

/// D_n(z) = psi_n'(z)/psi_n(z) for n = 0..terms by downward recurrence from a start order above
/// both `terms` and |z| (Wiscombe 1980), seeded exactly by the continued fraction.
/// T = double for the real argument x, Complex for mx.
template <typename T>
std::vector<T> logDerivatives(T z, int terms) {
    const int start = std::max(terms, static_cast<int>(std::ceil(magnitude(z)))) + 16;
    const T inverseZ = divide(T(1.0), z);
    std::vector<T> d(static_cast<size_t>(terms) + 1);
    T dn = besselRatioLentz(start, z) - static_cast<double>(start) * inverseZ;
    for (int n = start; n > 0; --n) {
        const T nz = static_cast<double>(n) * inverseZ;
        const T previous = nz - divide(T(1.0), dn + nz);  // D_{n-1}
        if (n <= terms) d[static_cast<size_t>(n)] = dn;
        dn = previous;
    }
    d[0] = dn;
    return d;
}

}  // namespace

int wiscombeTermCount(double x) {
    double cube = std::cbrt(x);
    double n = (x <= 8.0)     ? x + 4.0 * cube + 1.0
               : (x < 4200.0) ? x + 4.05 * cube + 2.0
                              : x + 4.0 * cube + 2.0;
    return std::max(1, static_cast<int>(n));
}

void checkMieInput(Complex m, double x) {
    if (!std::isfinite(x) || x <= 0.0 || x > 2e4)
        throw InputError("size parameter x must be in (0, 20000], got " + formatNumber(x));
    if (!std::isfinite(m.real()) || !std::isfinite(m.imag()) || m.real() <= 0.0)
        throw InputError("relative refractive index must have a positive finite real part, got " +
                         formatRefractiveIndex(m));
    if (m.imag() > 0.0)
        throw InputError("relative refractive index " + formatRefractiveIndex(m) +
                         " has a positive imaginary part: vpsim uses m = n - ik, so an absorbing "
                         "particle is written with a negative imaginary part (e.g. 1.5-0.1i)");
}

MieCoefficients mieCoefficients(Complex m, double x, int terms) {
    checkMieInput(m, x);
    if (terms <= 0) terms = wiscombeTermCount(x);
    const Complex mBH = std::conj(m);  // Bohren & Huffman convention inside this function
    const Complex inverseM = divide(1.0, mBH);
    const std::vector<Complex> dmx = logDerivatives(mBH * x, terms);
    const std::vector<double> dx = logDerivatives(x, terms);

    MieCoefficients c;
    c.x = x;
    c.m = m;
    c.a.resize(static_cast<size_t>(terms));
    c.b.resize(static_cast<size_t>(terms));
    // psi_n from psi_0 = sin x and psi_n = psi_{n-1} / (D_n(x) + n/x): exact for small x where
    // the upward recurrence would cancel. chi_n upward (it grows, so that direction is stable).
    double psiPrev = std::sin(x);
    double chiPrev = std::cos(x), chiPrevPrev = -std::sin(x);
    for (int n = 1; n <= terms; ++n) {
        const double nx = n / x;
        const double dxn = dx[static_cast<size_t>(n)];
        const double psi = psiPrev / (dxn + nx);
        const double chi = (2.0 * n - 1.0) / x * chiPrev - chiPrevPrev;
        const Complex xi(psi, -chi), xiPrev(psiPrev, -chiPrev);
        const Complex dm = dmx[static_cast<size_t>(n)];
        const Complex dmOverM = dm * inverseM, mDm = mBH * dm;
        const Complex an = divide(psi * (dmOverM - dxn), (dmOverM + nx) * xi - xiPrev);
        const Complex bn = divide(psi * (mDm - dxn), (mDm + nx) * xi - xiPrev);
        c.a[static_cast<size_t>(n - 1)] = std::conj(an);
        c.b[static_cast<size_t>(n - 1)] = std::conj(bn);
        psiPrev = psi;
        chiPrevPrev = chiPrev;
        chiPrev = chi;
    }
    return c;
}

MieEfficiencies mieEfficiencies(const MieCoefficients& c) {
    const int terms = c.terms();
    double ext = 0.0, sca = 0.0, asym = 0.0;
    Complex back = 0.0;
    for (int n = 1; n <= terms; ++n) {
        const Complex an = c.a[static_cast<size_t>(n - 1)], bn = c.b[static_cast<size_t>(n - 1)];
        const double w = 2.0 * n + 1.0;
        ext += w * (an.real() + bn.real());
        sca += w * (std::norm(an) + std::norm(bn));
        back += (n % 2 == 0 ? w : -w) * (an - bn);
        asym += w / (n * (n + 1.0)) * std::real(an * std::conj(bn));
        if (n < terms) {
            const Complex an1 = c.a[static_cast<size_t>(n)], bn1 = c.b[static_cast<size_t>(n)];
            asym +=
                n * (n + 2.0) / (n + 1.0) * std::real(an * std::conj(an1) + bn * std::conj(bn1));
        }
    }
    const double x2 = c.x * c.x;
    MieEfficiencies e;
    e.qext = 2.0 / x2 * ext;
    e.qsca = 2.0 / x2 * sca;
    // A real index cannot absorb: report exactly 0 instead of the rounding difference.
    e.qabs = (c.m.imag() == 0.0) ? 0.0 : e.qext - e.qsca;
    e.qback = std::norm(back) / x2;
    e.g = (sca > 0.0) ? 2.0 * asym / sca : 0.0;  // (4/x^2) sum / Qsca
    return e;
}

}  // namespace vpsim::optics
