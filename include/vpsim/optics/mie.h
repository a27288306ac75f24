#pragma once
/// @file
/// Lorenz-Mie scattering by a homogeneous sphere (seed 000 Eq. 3, 4, 9; Bohren & Huffman 1983
/// ch. 4; Wiscombe 1979/1980 NCAR/TN-140+STR).
///
/// Sign convention (used everywhere in vpsim, input and output): the relative refractive index is
/// m = n - i k with k >= 0, i.e. an ABSORBING particle has a NEGATIVE imaginary part ("1.5-0.1i").
/// This is the convention of van de Hulst and of Wiscombe's MIEV0 (time factor exp(+i w t)). The
/// returned a_n, b_n, S1, S2 are in that same convention; they are the complex conjugates of the
/// Bohren & Huffman (exp(-i w t), m = n + i k) values. Efficiencies and |S|^2 do not depend on the
/// convention. A positive imaginary part would describe a gain medium and is refused by
/// parseRefractiveIndex and checkMieInput; to use a Bohren & Huffman index "1.5+0.1i", write
/// "1.5-0.1i".
///
/// Qback is Bohren & Huffman's backscattering (radar) efficiency, as in their BHMIE program:
///   Qback = |sum (2n+1)(-1)^n (a_n - b_n)|^2 / x^2 = 4 |S1(180 deg)|^2 / x^2,
/// so Qback -> 1.5 Qsca in the Rayleigh limit. (Some codes divide this by 4 pi.)

#include <complex>
#include <string>
#include <vector>

namespace vpsim::optics {

using Complex = std::complex<double>;

/// Expansion coefficients of one sphere, n = 1..terms() stored at index n-1.
struct MieCoefficients {
    double x = 0.0;             ///< size parameter 2 pi r n_medium / lambda0
    Complex m{1.0, 0.0};        ///< relative index n_particle / n_medium, m = n - i k
    std::vector<Complex> a, b;  ///< a_n, b_n (exp(+i w t) convention), index n-1
    int terms() const { return static_cast<int>(a.size()); }
};

/// Efficiencies (cross-section / pi r^2) and asymmetry of one sphere.
struct MieEfficiencies {
    double qext = 0.0;   ///< extinction, 2/x^2 sum (2n+1) Re(a_n + b_n)
    double qsca = 0.0;   ///< scattering, 2/x^2 sum (2n+1)(|a_n|^2 + |b_n|^2)
    double qabs = 0.0;   ///< absorption, qext - qsca
    double qback = 0.0;  ///< Bohren & Huffman backscattering efficiency 4|S1(pi)|^2/x^2
    double g = 0.0;      ///< asymmetry parameter <cos theta>
};

/// Scattering amplitudes S1 (perpendicular) and S2 (parallel) at one angle.
struct MieAmplitudes {
    Complex s1, s2;
};

/// Number of terms by Wiscombe's criterion (x + 4 x^(1/3) + 1 up to x = 8, x + 4.05 x^(1/3) + 2
/// above up to 4200, x + 4 x^(1/3) + 2 beyond; Wiscombe, Appl. Opt. 19, 1505, 1980).
int wiscombeTermCount(double x);

/// Checks x and m. @throw InputError when x is not in (0, 2e4], m is not finite, Re(m) <= 0 or
/// Im(m) > 0 (see the sign convention above).
void checkMieInput(Complex m, double x);

/// Computes a_n and b_n with the downward logarithmic-derivative recurrence for D_n(mx) and
/// D_n(x), each seeded by Lentz's continued fraction, and psi_n(x) built from the D_n(x) ratios
/// (stable for small x, where the upward psi recurrence loses digits).
/// @param m relative index (n - i k), @param x size parameter
/// @param terms number of terms, 0 for wiscombeTermCount(x)
/// @throw InputError via checkMieInput
MieCoefficients mieCoefficients(Complex m, double x, int terms = 0);

/// Efficiencies and g from the coefficients (BH ch. 4: Qsca, Qext, Qback sums; g by the
/// a_n a*_{n+1} + b_n b*_{n+1} and a_n b*_n sums).
MieEfficiencies mieEfficiencies(const MieCoefficients& c);

/// S1, S2 at cos(theta) = mu (seed 000 Eq. 3) by the pi_n, tau_n recurrences.
MieAmplitudes mieAmplitudes(const MieCoefficients& c, double mu);

/// Unpolarised phase intensity K = (|S1|^2 + |S2|^2)/2 (seed 000 Eq. 2 averaged over phi) at
/// cos(theta) = mu. Its integral over the sphere is pi x^2 Qsca.
double miePhaseIntensity(const MieCoefficients& c, double mu);

/// Same at many angles (one pass per angle; no per-call allocation).
std::vector<double> miePhaseIntensity(const MieCoefficients& c, const std::vector<double>& mu);

/// Parses a refractive index "1.5", "1.5-0.1i", "1.5 - 0.1j", "1.5-i0.1".
/// @throw InputError (naming `what`) for malformed text or a positive imaginary part.
Complex parseRefractiveIndex(const std::string& text, const std::string& what = "refractive index");

/// Formats m as "1.5-0.1i".
std::string formatRefractiveIndex(Complex m);

}  // namespace vpsim::optics
