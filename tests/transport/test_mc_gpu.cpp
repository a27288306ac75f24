// The Vulkan photon Monte Carlo against the CPU path built from the same GLSL source. The two
// share every random number but not log/sin/cos to the last bit, so they agree within statistics
// (not bit for bit); each is exactly energy-balanced and reproducible on its own.

#include <catch2/catch.hpp>

#include <cmath>

#include "support/gpu_test.h"
#include "vpsim/transport/photon_mc.h"

using namespace vpsim;
using namespace vpsim::transport;

namespace {

McSetup matchedSlab(uint64_t photons) {
    McSetup s;
    s.optics.mua = 1.0;
    s.optics.mus = 9.0;
    s.optics.g = 0.75;
    s.thickness = 0.2;
    s.photons = photons;
    s.seed = 2024;
    return s;
}

bool agree(const Fraction& a, const Fraction& b, double sigmas) {
    return std::abs(a.value - b.value) <= sigmas * std::hypot(a.standardError, b.standardError);
}

}  // namespace

TEST_CASE("GPU photon MC matches van de Hulst and the CPU path", "[transport][gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    McSetup s = matchedSlab(100000);
    s.depths = {0.05, 0.1};
    McResult gpu = runPhotonMcGpu(s, ctx);
    McResult cpu = runPhotonMcCpu(s);
    INFO("GPU Rd " << gpu.diffuse().value << " Tt " << gpu.transmitted().value);
    CHECK(gpu.energyBalanced());
    CHECK(gpu.total().photons == s.photons);
    // Published values, 3 batch standard errors.
    CHECK(std::abs(gpu.diffuse().value - 0.09739) < 3 * gpu.diffuse().standardError);
    CHECK(std::abs(gpu.transmitted().value - 0.66096) < 3 * gpu.transmitted().standardError);
    // CPU vs GPU: 4 combined standard errors.
    CHECK(agree(gpu.diffuse(), cpu.diffuse(), 4));
    CHECK(agree(gpu.transmitted(), cpu.transmitted(), 4));
    CHECK(agree(gpu.absorbed(), cpu.absorbed(), 4));
    CHECK(agree(gpu.absorbedWithin(0), cpu.absorbedWithin(0), 4));
    CHECK(agree(gpu.absorbedWithin(1), cpu.absorbedWithin(1), 4));
    CHECK(std::abs(gpu.scatteringsPerPhoton() - cpu.scatteringsPerPhoton()) <
          0.05 * cpu.scatteringsPerPhoton());
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}

TEST_CASE("GPU photon MC with tabulated phase and Fresnel balances exactly and repeats",
          "[transport][gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    McSetup s = matchedSlab(40000);
    s.optics.refractiveIndex = 1.45;
    s.optics.mus = 30.0;
    s.optics.phase = optics::PhaseModel::Tabulated;
    for (int i = 0; i < 2001; ++i) {  // HG g = 0.8 inverse CDF, +1 at u = 0
        double g = 0.8, u = i / 2000.0, t = (1 - g * g) / (1 - g + 2 * g * (1 - u));
        s.optics.inverseCdf.push_back(float(std::clamp((1 + g * g - t * t) / (2 * g), -1.0, 1.0)));
    }
    s.beam = BeamShape::Gaussian;
    s.lateralRadius = 0.15;
    s.grid = {0.02, 12, 10};
    McResult a = runPhotonMcGpu(s, ctx);
    McResult b = runPhotonMcGpu(s, ctx);
    McResult cpu = runPhotonMcCpu(s);
    CHECK(a.energyBalanced());
    // Same seed on the GPU: identical integer tallies whatever the scheduling of invocations.
    CHECK(a.absorbedRZ == b.absorbedRZ);
    CHECK(a.absorbedGrid == b.absorbedGrid);
    CHECK(a.total().diffuse == b.total().diffuse);
    CHECK(a.specular().value == cpu.specular().value);  // deterministic split
    CHECK(agree(a.diffuse(), cpu.diffuse(), 4));
    CHECK(agree(a.escaped(), cpu.escaped(), 4));
    CHECK(agree(a.transmitted(), cpu.transmitted(), 4));
    // The Cartesian grid holds no more than the absorbed total; the near-surface voxels agree
    // with the CPU within 4 binomial sigmas.
    uint64_t gridSum = 0, cpuSum = 0;
    for (uint64_t q : a.absorbedGrid) gridSum += q;
    for (uint64_t q : cpu.absorbedGrid) cpuSum += q;
    CHECK(gridSum <= a.total().absorbed);
    double pa = double(gridSum) / a.launched(), pc = double(cpuSum) / cpu.launched();
    CHECK(std::abs(pa - pc) < 4 * std::sqrt(2 * pa * (1 - pa) / s.photons));
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}
