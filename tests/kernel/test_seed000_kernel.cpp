// Seed 000 Section II-C findings on its alumina slurry (50 vol% Al2O3, R = 2.5 um, 405 nm,
// W0 = 50 um, P = 10 mW; optics from examples/materials/alumina-seed000.json via Mie theory):
// scattering makes the cure shallower and wider than Beer-Lambert alone, the fitted Gaussian
// radius stays close to W0, and the intensity maximum lies below the surface.
// CPU path, track-length estimator, 200k photons per run (its bins carry the information of
// several times as many analog photons: see bench_photon_mc), fixed seeds; the bounds leave
// several standard errors of margin.

#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/transport/photon_mc.h"

using namespace vpsim;
using namespace vpsim::kernel;

namespace {

BeamKernel runSeed000Kernel(double nOutside) {
    transport::McSetup s;
    s.optics =
        optics::loadMediumOptics(VPSIM_SOURCE_DIR "/examples/materials/alumina-seed000.json");
    s.beam = transport::BeamShape::Gaussian;
    s.w0 = 0.05;
    s.nAbove = nOutside;
    s.photons = 200000;
    s.seed = 1;
    s.bins = {0.2, 0.06, 24, 24};  // 8.3 um x 2.5 um bins: resolves the first few um
    return kernelFromMonteCarlo(transport::runPhotonMcCpu(s), 10.0);
}

/// Cached within one test process (both test cases use the run under air).
const BeamKernel& seed000Kernel(double nOutside) {
    if (nOutside == 1.0) {
        static const BeamKernel air = runSeed000Kernel(1.0);
        return air;
    }
    static const BeamKernel matched = runSeed000Kernel(nOutside);
    return matched;
}

/// Depth and surface half-width of the iso-intensity contour at `level` for the fitted model.
void contour(double amplitude, double w, double d, double level, double& depth, double& halfWidth) {
    double ratio = std::log(amplitude / level);
    depth = d * ratio;
    halfWidth = w * std::sqrt(ratio / 2);
}

}  // namespace

TEST_CASE("seed 000 slurry: cure shallower and wider than Beer-Lambert with a radius close to W0",
          "[kernel]") {
    const BeamKernel& k = seed000Kernel(1.0);  // resin under air: Fresnel at the top surface
    const double dp0 = 0.119, w0 = 0.05;
    INFO("We3D " << k.fit.we3d << " De3D " << k.fit.de3d << " A " << k.fit.amplitude << " zmax "
                 << k.zmax);
    CHECK(k.mua == Approx(1 / dp0).epsilon(1e-3));
    CHECK(k.fit.de3d < 0.5 * dp0);                 // measured ~36 um vs 119 um
    CHECK(k.fit.amplitude > k.beerLambert(0, 0));  // peak raised by scattered light (~1.5x)
    CHECK(k.fit.we3d > w0);                        // broadened ...
    CHECK(k.fit.we3d < 1.4 * w0);                  // ... but close to W0 (~1.25 W0)
    // Contour at 10% of the unscattered peak intensity: shallower and wider.
    const double level = 0.1 * k.beerLambert(0, 0);
    double depthBL, widthBL, depthMC, widthMC;
    contour(k.beerLambert(0, 0), w0, dp0, level, depthBL, widthBL);
    contour(k.fit.amplitude, k.fit.we3d, k.fit.de3d, level, depthMC, widthMC);
    CHECK(depthMC < 0.6 * depthBL);
    CHECK(widthMC > 1.3 * widthBL);  // measured 1.46x
    // The same from the table itself: at the Beer-Lambert contour depth the MC intensity is far
    // below the level, and at the Beer-Lambert surface half-width it is above it.
    CHECK(k.sample(0, depthBL) < 0.5 * level);
    CHECK(k.sample(widthBL, 0.005) > level);
    CHECK(k.fit.residual < 0.3);
    // Energy: the least-squares fit carries less than the table (the near-surface peak and the
    // wide halo lie outside Eq. 12); the energy-conserving variant carries it all by construction.
    INFO("fit energy fraction " << k.fit.energyFraction);
    CHECK(k.fit.energyFraction > 0.7);
    CHECK(k.fit.energyFraction < 1.0);
    CHECK(k.energyFit.energyFraction == 1.0);
    CHECK(k.energyFit.amplitude > k.fit.amplitude);
}

TEST_CASE("seed 000 slurry: intensity maximum below the surface when photons escape freely",
          "[kernel]") {
    // The seed's MC lets photons leave through the top (no Fresnel): with an index-matched top
    // surface the maximum of Ie(0, z) lies a few um down. Under air, total internal reflection
    // keeps scattered light near the surface and the maximum moves up to z = 0.
    const BeamKernel& matched = seed000Kernel(1.45);
    const BeamKernel& air = seed000Kernel(1.0);
    // Mean slice amplitude 2.5-10 um deep over the amplitude of the top 2.5 um slice: measured
    // 1.018-1.030 matched, 0.957-0.968 under air (seeds 1-3); slice noise is ~1%.
    auto rise = [](const BeamKernel& k) {
        return (k.depthAmplitude[1] + k.depthAmplitude[2] + k.depthAmplitude[3]) /
               (3 * k.depthAmplitude[0]);
    };
    INFO("zmax matched " << matched.zmax << " air " << air.zmax << "; rise matched "
                         << rise(matched) << " air " << rise(air));
    CHECK(rise(matched) > 1.0);
    CHECK(rise(air) < 1.0);
    // Sub-bin zmax: a few um for the matched top (issue 14: about 5.7 um), exactly 0 under air,
    // where Ie(0, z) falls from the surface.
    CHECK(matched.zmax > 0.003);
    CHECK(matched.zmax < 0.009);
    CHECK(air.zmax == 0.0);
}
