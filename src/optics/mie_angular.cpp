// Angular Mie functions: S1, S2 (seed 000 Eq. 3) and the unpolarised intensity K at many angles.

#include <algorithm>
#include <array>

#include "vpsim/optics/mie.h"

namespace vpsim::optics {

MieAmplitudes mieAmplitudes(const MieCoefficients& c, double mu) {
    // pi_n and tau_n (BH Eq. 4.47): pi_0 = 0, pi_1 = 1,
    // pi_{n+1} = ((2n+1) mu pi_n - (n+1) pi_{n-1}) / n, tau_n = n mu pi_n - (n+1) pi_{n-1}.
    Complex s1 = 0.0, s2 = 0.0;
    double piPrev = 0.0, pi = 1.0;
    const int terms = c.terms();
    for (int n = 1; n <= terms; ++n) {
        const double tau = n * mu * pi - (n + 1.0) * piPrev;
        const double w = (2.0 * n + 1.0) / (n * (n + 1.0));
        const Complex an = c.a[static_cast<size_t>(n - 1)], bn = c.b[static_cast<size_t>(n - 1)];
        s1 += w * (an * pi + bn * tau);
        s2 += w * (an * tau + bn * pi);
        const double piNext = ((2.0 * n + 1.0) * mu * pi - (n + 1.0) * piPrev) / n;
        piPrev = pi;
        pi = piNext;
    }
    return {s1, s2};
}

double miePhaseIntensity(const MieCoefficients& c, double mu) {
    MieAmplitudes s = mieAmplitudes(c, mu);
    return 0.5 * (std::norm(s.s1) + std::norm(s.s2));
}

std::vector<double> miePhaseIntensity(const MieCoefficients& c, const std::vector<double>& mu) {
    // Same sums as mieAmplitudes, arranged for speed: the weights (2n+1)/(n(n+1)) a_n, b_n and the
    // recurrence constants are precomputed in real arrays, and BLOCK angles advance together so
    // the inner loop over angles vectorises. S1 + S2 and S1 - S2 need only (a+b) and (a-b):
    // S1 +- S2 = sum w (a +- b)(pi +- tau), and (|S1|^2+|S2|^2)/2 = (|S+|^2 + |S-|^2)/4.
    constexpr size_t BLOCK = 32;
    const size_t terms = static_cast<size_t>(c.terms());
    std::vector<double> sumRe(terms), sumIm(terms), diffRe(terms), diffIm(terms), r1(terms),
        r2(terms);
    for (size_t i = 0; i < terms; ++i) {
        const double n = static_cast<double>(i + 1);
        const double w = (2.0 * n + 1.0) / (n * (n + 1.0));
        sumRe[i] = w * (c.a[i].real() + c.b[i].real());
        sumIm[i] = w * (c.a[i].imag() + c.b[i].imag());
        diffRe[i] = w * (c.a[i].real() - c.b[i].real());
        diffIm[i] = w * (c.a[i].imag() - c.b[i].imag());
        r1[i] = (2.0 * n + 1.0) / n;  // pi_{n+1} = r1 mu pi_n - r2 pi_{n-1}
        r2[i] = (n + 1.0) / n;
    }
    std::vector<double> k(mu.size());
    for (size_t start = 0; start < mu.size(); start += BLOCK) {
        const size_t count = std::min(BLOCK, mu.size() - start);
        std::array<double, BLOCK> m{}, pi{}, piPrev{}, pRe{}, pIm{}, qRe{}, qIm{};
        for (size_t j = 0; j < BLOCK; ++j) {
            m[j] = j < count ? mu[start + j] : 0.0;
            pi[j] = 1.0;
        }
        for (size_t i = 0; i < terms; ++i) {
            const double n = static_cast<double>(i + 1);
            for (size_t j = 0; j < BLOCK; ++j) {
                const double tau = n * m[j] * pi[j] - (n + 1.0) * piPrev[j];
                const double plus = pi[j] + tau, minus = pi[j] - tau;
                pRe[j] += sumRe[i] * plus;
                pIm[j] += sumIm[i] * plus;
                qRe[j] += diffRe[i] * minus;
                qIm[j] += diffIm[i] * minus;
                const double next = r1[i] * m[j] * pi[j] - r2[i] * piPrev[j];
                piPrev[j] = pi[j];
                pi[j] = next;
            }
        }
        for (size_t j = 0; j < count; ++j)
            k[start + j] =
                0.25 * (pRe[j] * pRe[j] + pIm[j] * pIm[j] + qRe[j] * qRe[j] + qIm[j] * qIm[j]);
    }
    return k;
}

}  // namespace vpsim::optics
