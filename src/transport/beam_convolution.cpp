#include "vpsim/transport/beam_convolution.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "photon_params.h"

namespace vpsim::transport {
namespace {

constexpr uint32_t REFINE = 2;           // pencil rings per output ring
constexpr double OUTER_SIGMAS = 6.0;     // the launch offset's reach (exp(-18) beyond it)
constexpr double MIN_W0_IN_RINGS = 4.0;  // narrower beams are tallied directly
constexpr double MAX_PRODUCTS = 1e9;     // multiply-adds of the convolution (about a second)

/// The launch offset's standard deviation per axis: intensity exp(-2 r^2 / W0^2).
double sigmaOf(double w0) {
    return 0.5 * w0;
}

uint32_t pencilRings(const McSetup& s) {
    const double width = s.bins.rMax / s.bins.rBins / REFINE;
    return s.bins.rBins * REFINE + uint32_t(std::ceil(OUTER_SIGMAS * sigmaOf(s.w0) / width));
}

/// e^-x I0(x) for x >= 0 (Abramowitz & Stegun 9.8.1-2, relative error < 2e-7), without the
/// overflow of I0 itself.
double scaledBesselI0(double x) {
    if (x <= 3.75) {
        const double t = (x / 3.75) * (x / 3.75);
        const double i0 =
            1.0 + t * (3.5156229 +
                       t * (3.0899424 +
                            t * (1.2067492 + t * (0.2659732 + t * (0.0360768 + t * 0.0045813)))));
        return std::exp(-x) * i0;
    }
    const double t = 3.75 / x;
    const double p =
        0.39894228 +
        t * (0.01328592 +
             t * (0.00225319 +
                  t * (-0.00157565 +
                       t * (0.00916281 +
                            t * (-0.02057706 +
                                 t * (0.02635537 + t * (-0.01647633 + t * 0.00392377)))))));
    return p / std::sqrt(x);
}

/// Density of |rho e_x + offset| at r (Rice, offset Gaussian with `sigma` per axis), 1/mm.
double rice(double r, double rho, double sigma) {
    const double s2 = sigma * sigma;
    return r / s2 * std::exp(-0.5 * (r - rho) * (r - rho) / s2) * scaledBesselI0(r * rho / s2);
}

// 4-point Gauss-Legendre on [-1, 1].
constexpr std::array<double, 4> GL_X{-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                     0.8611363115940526};
constexpr std::array<double, 4> GL_W{0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                     0.3478548451374538};

/// convolveRings of quanta, rounded back to quanta.
void convolveRows(const uint64_t* in, uint64_t* out, size_t rows, uint32_t pencilBins,
                  uint32_t rings, const std::vector<double>& w) {
    std::vector<double> sums(rows * rings);
    convolveRings(in, sums.data(), rows, pencilBins, rings, w);
    for (size_t i = 0; i < sums.size(); ++i) out[i] = uint64_t(std::llround(sums[i]));
}

}  // namespace

bool convolvesBeam(const McSetup& s) {
    if (!s.beamConvolution || s.beam != BeamShape::Gaussian || s.lateralRadius > 0 ||
        s.grid.nxy > 0)
        return false;
    if (!(s.w0 >= MIN_W0_IN_RINGS * s.bins.rMax / s.bins.rBins)) return false;
    const uint64_t copies = s.binsPerBatch ? MC_BATCHES : 1;
    const uint64_t bins = uint64_t(pencilRings(s)) * s.bins.zBins * copies;
    return bins <= MAX_RZ_BINS && double(bins) * s.bins.rBins <= MAX_PRODUCTS;
}

McSetup pencilSetup(const McSetup& s) {
    McSetup p = s;
    p.beam = BeamShape::Pencil;
    p.beamConvolution = false;
    p.bins.rBins = pencilRings(s);
    p.bins.rMax = p.bins.rBins * (s.bins.rMax / s.bins.rBins / REFINE);
    return p;
}

std::vector<double> ringWeights(uint32_t rings, double ringWidth, uint32_t pencilBins,
                                double pencilWidth, double w0) {
    const double sigma = sigmaOf(w0), reach = 8.0 * sigma;
    std::vector<double> w(size_t(rings) * pencilBins, 0.0);
    for (uint32_t j = 0; j < pencilBins; ++j) {
        // Points uniform over the pencil ring's area: Gauss-Legendre in rho^2.
        const double a2 = std::pow(j * pencilWidth, 2), b2 = std::pow((j + 1) * pencilWidth, 2);
        for (size_t q = 0; q < GL_X.size(); ++q) {
            const double rho = std::sqrt(0.5 * (a2 + b2) + 0.5 * (b2 - a2) * GL_X[q]);
            for (uint32_t i = 0; i < rings; ++i) {
                const double c = i * ringWidth, d = (i + 1) * ringWidth;
                if (c > rho + reach || d < rho - reach) continue;  // below 1e-14
                double p = 0.0;
                for (size_t k = 0; k < GL_X.size(); ++k)
                    p += GL_W[k] * rice(0.5 * (c + d) + 0.5 * (d - c) * GL_X[k], rho, sigma);
                w[size_t(i) * pencilBins + j] += 0.5 * GL_W[q] * 0.5 * (d - c) * p;
            }
        }
    }
    return w;
}

McResult convolveBeam(const McResult& pencil, const McSetup& setup) {
    const auto start = std::chrono::steady_clock::now();
    const CylindricalGrid& in = pencil.setup.bins;
    const CylindricalGrid& out = setup.bins;
    const std::vector<double> w =
        ringWeights(out.rBins, out.rMax / out.rBins, in.rBins, in.rMax / in.rBins, setup.w0);
    McResult r;
    r.setup = setup;
    r.launchWeight = pencil.launchWeight;
    r.batches = pencil.batches;
    r.controlBatches = pencil.controlBatches;
    r.backend = pencil.backend;
    const size_t outBins = size_t(out.rBins) * out.zBins, inBins = size_t(in.rBins) * in.zBins;
    if (setup.binsPerBatch) {
        r.absorbedRZBatches.assign(outBins * MC_BATCHES, 0);
        r.absorbedRZ.assign(outBins, 0);
        for (size_t b = 0; b < size_t(MC_BATCHES); ++b) {
            convolveRows(pencil.absorbedRZBatches.data() + b * inBins,
                         r.absorbedRZBatches.data() + b * outBins, out.zBins, in.rBins, out.rBins,
                         w);
            for (size_t i = 0; i < outBins; ++i)
                r.absorbedRZ[i] += r.absorbedRZBatches[b * outBins + i];
        }
    } else {
        r.absorbedRZ.assign(outBins, 0);
        convolveRows(pencil.absorbedRZ.data(), r.absorbedRZ.data(), out.zBins, in.rBins, out.rBins,
                     w);
    }
    r.seconds = pencil.seconds +
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

}  // namespace vpsim::transport
