// The Gaussian beam from the convolved pencil response (transport/beam_convolution.h): the ring
// weights against the closed form on the axis and a brute-force 2D integral off it, and the
// convolved bins against directly launched Gaussian photons (same expectation, less variance near
// the axis), on the CPU path and on the GPU.

#include <catch2/catch.hpp>

#include <cmath>

#include "mc_test_support.h"
#include "support/gpu_test.h"
#include "vpsim/transport/beam_convolution.h"
#include "vpsim/transport/photon_mc.h"

using namespace vpsim;
using namespace vpsim::transport;
using vpsim::test::agree;
using vpsim::test::binsFraction;

namespace {

McSetup slurryLike(uint64_t photons) {
    McSetup s;  // issue 14's slurry-like HG medium under a Gaussian beam
    s.optics.mua = 8.4;
    s.optics.mus = 303.0;
    s.optics.g = 0.9;
    s.beam = BeamShape::Gaussian;
    s.w0 = 0.05;
    s.bins = {0.2, 0.36, 40, 36};
    s.binsPerBatch = true;
    s.photons = photons;
    s.seed = 77;
    s.estimator = Estimator::Analog;
    return s;
}

}  // namespace

TEST_CASE("ring weights of a point on the axis are the Gaussian's ring energies",
          "[transport][convolution]") {
    // A pencil ring of 1 nm holds the axis: ring i gets exp(-2 c^2/W0^2) - exp(-2 d^2/W0^2).
    const double w0 = 0.05, width = 0.005;
    std::vector<double> w = ringWeights(40, width, 1, 1e-6, w0);
    double sum = 0;
    for (int i = 0; i < 40; ++i) {
        const double c = i * width, d = c + width;
        const double exact = std::exp(-2 * c * c / (w0 * w0)) - std::exp(-2 * d * d / (w0 * w0));
        CHECK(w[size_t(i)] == Approx(exact).margin(2e-6));
        sum += w[size_t(i)];
    }
    CHECK(sum == Approx(1.0).margin(1e-5));  // 0.2 mm = 8 W0 holds it all
}

TEST_CASE("ring weights off the axis match a brute-force integral", "[transport][convolution]") {
    // Pencil ring 30 of 2.5 um (rho 75-77.5 um), output rings of 5 um, W0 40 um: each weight
    // against a midpoint integral of the Gaussian offset over the output ring (in polar
    // coordinates), averaged over the pencil ring's area.
    const double w0 = 0.04, sigma2 = w0 * w0 / 4, pencil = 0.0025, ring = 0.005;
    const uint32_t j = 30;
    std::vector<double> w = ringWeights(60, ring, j + 1, pencil, w0);
    double sum = 0;
    for (uint32_t i = 0; i < 60; ++i) {
        double brute = 0, areaWeight = 0;
        for (int a = 0; a < 8; ++a) {  // rho points, weighted by rho (area)
            const double rho = (j + (a + 0.5) / 8) * pencil;
            double p = 0;
            const int nr = 20, nt = 720;
            for (int u = 0; u < nr; ++u)
                for (int t = 0; t < nt; ++t) {
                    const double r = (i + (u + 0.5) / nr) * ring, th = (t + 0.5) * 2 * M_PI / nt;
                    const double dx = r * std::cos(th) - rho, dy = r * std::sin(th);
                    p += std::exp(-(dx * dx + dy * dy) / (2 * sigma2)) / (2 * M_PI * sigma2) * r *
                         (ring / nr) * (2 * M_PI / nt);
                }
            brute += rho * p;
            areaWeight += rho;
        }
        brute /= areaWeight;
        INFO("output ring " << i);
        CHECK(w[size_t(i) * (j + 1) + j] == Approx(brute).margin(2e-5));
        sum += w[size_t(i) * (j + 1) + j];
    }
    CHECK(sum == Approx(1.0).margin(1e-4));
}

TEST_CASE("convolved pencil bins equal directly launched Gaussian bins, with less variance",
          "[transport][convolution]") {
    McSetup direct = slurryLike(60000);
    direct.beamConvolution = false;
    McSetup convolved = slurryLike(60000);
    convolved.seed = 78;
    REQUIRE(convolvesBeam(convolved));
    REQUIRE_FALSE(convolvesBeam(direct));
    McResult d = runPhotonMcCpu(direct), c = runPhotonMcCpu(convolved);
    CHECK(c.energyBalanced());
    CHECK(c.absorbedRZ.size() == d.absorbedRZ.size());
    CHECK(c.setup.bins.rBins == 40);
    // Surface, cure front and deep bins, near the axis and beyond the beam radius.
    for (auto [z0, z1] : {std::pair{0u, 4u}, std::pair{4u, 12u}, std::pair{12u, 36u}})
        for (auto [r0, r1] : {std::pair{0u, 2u}, std::pair{2u, 10u}, std::pair{10u, 40u}}) {
            Fraction fd = binsFraction(d, z0, z1, r0, r1), fc = binsFraction(c, z0, z1, r0, r1);
            INFO("z " << z0 << ".." << z1 << " r " << r0 << ".." << r1 << ": direct " << fd.value
                      << " +- " << fd.standardError << ", convolved " << fc.value << " +- "
                      << fc.standardError);
            CHECK(agree(fc, fd, 3.0));
        }
    // The two rings on the axis at the cure front: the launch offset's spread dominated their
    // variance, so the convolution cuts it several-fold at the same photon count.
    CHECK(binsFraction(c, 4, 12, 0, 2).standardError <
          0.5 * binsFraction(d, 4, 12, 0, 2).standardError);
}

TEST_CASE("GPU beam convolution matches the CPU path", "[transport][convolution][gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    McSetup s = slurryLike(30000);
    s.estimator = Estimator::Collision;
    McResult gpu = runPhotonMcGpu(s, ctx), cpu = runPhotonMcCpu(s);
    CHECK(gpu.energyBalanced());
    CHECK(gpu.absorbedRZ.size() == cpu.absorbedRZ.size());
    for (auto [r0, r1] : {std::pair{0u, 4u}, std::pair{4u, 40u}})
        CHECK(agree(binsFraction(gpu, 4, 12, r0, r1), binsFraction(cpu, 4, 12, r0, r1), 4.0));
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}
