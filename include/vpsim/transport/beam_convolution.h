#pragma once
/// @file
/// A Gaussian beam's (r,z) absorption from the pencil-beam response (the idea of MCML's
/// CONV program, done inside the run). In a laterally unbounded medium the response to a photon
/// launched at (x0, y0) is the pencil response shifted by (x0, y0), so the Gaussian beam's bins are
/// the pencil bins convolved with the beam profile. Tracing pencil photons and convolving replaces
/// the random launch offset by its expectation (a conditional Monte Carlo estimator): the same
/// expected bins with far less variance near the axis, where the rings are small.
///
/// The pencil response is tallied on a radial grid REFINE times finer than the output and wider by
/// the beam's reach (OUTER_SIGMAS standard deviations), and each pencil bin is spread over the
/// output rings with the ring probabilities of the shifted Gaussian (Rice distribution), averaged
/// over the bin's area. Used when the beam is Gaussian, there is no lateral radius and no
/// Cartesian grid (those need the photons' true positions), and the beam is wide against the
/// output rings (W0 >= MIN_W0_IN_RINGS ring widths; narrower beams gain little), and while the
/// pencil tally fits MAX_RZ_BINS and the convolution stays within about a second.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "vpsim/transport/photon_mc.h"

namespace vpsim::transport {

/// Whether runs of `setup` trace the pencil response and convolve it with the beam.
bool convolvesBeam(const McSetup& setup);

/// The pencil-beam run traced for a setup that convolvesBeam: same medium and photons, pencil
/// beam, radial bins refined and widened, beam convolution off.
McSetup pencilSetup(const McSetup& setup);

/// Ring weights: weights[i * pencilBins + j] is the probability that a point absorbed in pencil
/// ring j (uniform over its area, rings of width pencilWidth) lands in output ring i (width
/// ringWidth, `rings` of them) once shifted by the beam's launch offset (Gaussian of 1/e^2
/// intensity radius w0). Columns sum to the fraction landing inside the output grid. mm.
std::vector<double> ringWeights(uint32_t rings, double ringWidth, uint32_t pencilBins,
                                double pencilWidth, double w0);

/// Applies ring weights (ringWeights) to `rows` rows: out[z * rings + i] = sum over j of
/// weights[i * pencilBins + j] * in[z * pencilBins + j].
template <class Value>
void convolveRings(const Value* in, double* out, size_t rows, uint32_t pencilBins, uint32_t rings,
                   const std::vector<double>& weights) {
    for (size_t z = 0; z < rows; ++z) {
        const Value* row = in + z * pencilBins;
        for (uint32_t i = 0; i < rings; ++i) {
            const double* wi = weights.data() + size_t(i) * pencilBins;
            double sum = 0.0;
            for (uint32_t j = 0; j < pencilBins; ++j) sum += wi[j] * double(row[j]);
            out[z * rings + i] = sum;
        }
    }
}

/// The result of `setup` from the pencil run `pencil` (of pencilSetup(setup)): the totals as
/// traced, the (r,z) bins (and per-batch bins) convolved with the beam and rounded to quanta.
McResult convolveBeam(const McResult& pencil, const McSetup& setup);

}  // namespace vpsim::transport
