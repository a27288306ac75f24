// Beam kernel: the Eq. 12 fit against synthetic fields with known parameters, the Eq. 11
// normalisation against Beer-Lambert, JSON/VDB output, and bad inputs.

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/transport/photon_mc.h"

using namespace vpsim;
using namespace vpsim::kernel;

namespace {

/// A kernel table filled with amplitude(z) exp(-2 r^2 / W^2) at bin centres.
template <class Amplitude>
BeamKernel synthetic(double w, Amplitude amplitude, double noise = 0.0, uint32_t seed = 1) {
    BeamKernel k;
    k.power = 10;
    k.w0 = w;
    k.mua = 8.4;
    k.rBins = 50;
    k.zBins = 60;
    k.rBin = 0.004;
    k.zBin = 0.005;
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss(0.0, noise);
    for (uint32_t iz = 0; iz < k.zBins; ++iz)
        for (uint32_t ir = 0; ir < k.rBins; ++ir) {
            double r = (ir + 0.5) * k.rBin, z = (iz + 0.5) * k.zBin;
            double value = amplitude(z) * std::exp(-2 * r * r / (w * w));
            k.intensity.push_back(float(value * (noise > 0 ? std::exp(gauss(rng)) : 1.0)));
        }
    return k;
}

std::string tempPath(const std::string& name) {
    return std::string("/tmp/vpsim_test_kernel_") + name;
}

}  // namespace

TEST_CASE("Eq. 12 fit recovers a synthetic Gaussian x exponential field", "[kernel]") {
    // Exact model at bin centres: the log-linear fit is exact up to float rounding (1e-4).
    const double a0 = 3000, w = 0.06, d = 0.04;
    BeamKernel k = synthetic(w, [&](double z) { return a0 * std::exp(-z / d); });
    fitKernel(k);
    CHECK(k.fit.we3d == Approx(w).epsilon(1e-4));
    CHECK(k.fit.de3d == Approx(d).epsilon(1e-4));
    CHECK(k.fit.amplitude == Approx(a0).epsilon(1e-4));
    CHECK(k.fit.residual < 1e-4);
    CHECK(k.zmax == 0.0);  // Ie(0, z) falls from the surface: exactly 0, not half a bin
    // Eq. 12 sampled at bin centres against its closed-form integral over the table: the
    // midpoint rule errs by (zBin / d)^2 / 24 = 0.07% in z and less across r.
    CHECK(k.fit.energyFraction == Approx(1.0).epsilon(0.003));
    CHECK(k.energyFit.amplitude == Approx(a0).epsilon(0.003));
    CHECK(k.energyFit.energyFraction == 1.0);
    for (uint32_t iz = 0; iz < 20; ++iz) CHECK(k.depthRadius[iz] == Approx(w).epsilon(1e-4));
    CHECK(k.fitted(0.01, 0.02) ==
          Approx(a0 * std::exp(-2e-4 / (w * w)) * std::exp(-0.5)).epsilon(1e-4));

    // 10% multiplicative noise (fixed seed): parameters within 2%, residual reflects the noise.
    BeamKernel noisy = synthetic(
        w, [&](double z) { return a0 * std::exp(-z / d); }, 0.10, 7);
    fitKernel(noisy);
    CHECK(noisy.fit.we3d == Approx(w).epsilon(0.02));
    CHECK(noisy.fit.de3d == Approx(d).epsilon(0.02));
    CHECK(noisy.fit.residual > 0.05);
    CHECK(noisy.fit.residual < 0.2);
}

TEST_CASE("a sub-surface maximum is located and the fit starts there", "[kernel]") {
    // Amplitude (1 - 0.6 exp(-z/z1)) exp(-z/d) peaks at z* = z1 ln(0.6 (d + z1) / z1).
    const double z1 = 0.01, d = 0.05;
    auto amplitude = [&](double z) {
        return 2000 * (1 - 0.6 * std::exp(-z / z1)) * std::exp(-z / d);
    };
    const double expected = z1 * std::log(0.6 * (d + z1) / z1);
    BeamKernel k = synthetic(0.05, amplitude);
    fitKernel(k);
    INFO("zmax " << k.zmax << " expected " << expected);
    CHECK(std::abs(k.zmax - expected) <
          0.5 * k.zBin);  // parabola over 5 slices of a skewed peak: half a bin
    CHECK(k.fit.fitDepthStart >= k.zmax - 0.5 * k.zBin);
    CHECK(k.fit.we3d == Approx(0.05).epsilon(0.01));  // z-misfit leaks slightly into r
    // Below zmax the amplitude decays more slowly than exp(-z/d) alone would suggest near the
    // top, but never faster: the fitted De lies between d and 2d.
    CHECK(k.fit.de3d > d);
    CHECK(k.fit.de3d < 2 * d);
}

TEST_CASE("Eq. 11 on an unscattered Gaussian beam gives the Beer-Lambert intensity", "[kernel]") {
    // No scattering: I(r,z) = (1 - Rsp) 2P/(pi W0^2) exp(-2r^2/W0^2) exp(-mua z). The MC kernel
    // must give back W0, 1/mua and the peak within 3% (200k photons; photon noise in the
    // weighted fits is ~1%).
    transport::McSetup s;
    s.optics.mua = 8.4;
    s.optics.refractiveIndex = 1.45;
    s.beam = transport::BeamShape::Gaussian;
    s.w0 = 0.05;
    s.photons = 200000;
    s.seed = 3;
    s.bins = {0.15, 0.3, 30, 30};
    BeamKernel k = kernelFromMonteCarlo(transport::runPhotonMcCpu(s), 10.0);
    const double peak =
        (1 - std::pow(0.45 / 2.45, 2)) * 2 * 10.0 / (3.14159265358979 * 0.05 * 0.05);
    CHECK(k.beerLambert(0, 0) == Approx(peak).epsilon(1e-6));
    CHECK(k.fit.we3d == Approx(0.05).epsilon(0.03));
    CHECK(k.fit.de3d == Approx(1 / 8.4).epsilon(0.03));
    CHECK(k.fit.amplitude == Approx(peak).epsilon(0.03));
    CHECK(k.sample(0.03, 0.1) == Approx(k.beerLambert(0.03, 0.1)).epsilon(0.1));
}

TEST_CASE("beam kernel JSON round trip and output files", "[kernel]") {
    BeamKernel k = synthetic(
        0.05, [](double z) { return 1500 * std::exp(-z / 0.03); }, 0.05, 11);
    fitKernel(k);
    k.specularReflectance = 0.0337;
    k.photons = 123456;
    const std::string path = tempPath("roundtrip.json");
    k.save(path);
    BeamKernel back = BeamKernel::load(path);
    CHECK(back.intensity == k.intensity);  // floats survive JSON exactly
    CHECK(back.depthAmplitude == k.depthAmplitude);
    CHECK(back.fit.we3d == Approx(k.fit.we3d).epsilon(1e-12));
    CHECK(back.fit.de3d == Approx(k.fit.de3d).epsilon(1e-12));
    CHECK(back.zmax == Approx(k.zmax).epsilon(1e-12));
    CHECK(back.fit.residual == k.fit.residual);
    CHECK(back.photons == k.photons);
    CHECK(back.sample(0.02, 0.05) == Approx(k.sample(0.02, 0.05)));
    std::remove(path.c_str());

    const std::string vdb = tempPath("kernel.vdb");
    writeKernelVdb(vdb, k);
    std::ifstream in(vdb, std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    CHECK(std::string(magic, 4) == " BDV");  // OpenVDB file magic 0x56444220, little endian
    std::remove(vdb.c_str());

    const std::string dir = tempPath("figures");
    writeKernelFigures(dir, k);
    for (const char* name : {"intensity_scattered.png", "intensity_no_scattering.png",
                             "intensity_fit.png", "amplitude_vs_depth.svg", "radius_vs_depth.svg",
                             "contours_scattering.svg", "contours_fit.svg"}) {
        std::ifstream file(dir + "/" + name, std::ios::binary | std::ios::ate);
        INFO(name);
        CHECK(file.good());
        CHECK(file.tellg() > 1000);
        std::remove((dir + "/" + name).c_str());
    }
    std::remove(dir.c_str());
}

TEST_CASE("bad beam kernel inputs give clear errors", "[kernel]") {
    CHECK_THROWS_AS(BeamKernel::load(tempPath("does_not_exist.json")), InputError);
    const std::string path = tempPath("bad.json");
    {
        std::ofstream out(path);
        out << R"({"format": "something-else"})";
    }
    CHECK_THROWS_WITH(BeamKernel::load(path), Catch::Contains("not a beam kernel"));
    BeamKernel k = synthetic(0.05, [](double z) { return 100 * std::exp(-z / 0.03); });
    fitKernel(k);
    nlohmann::json j = k.toJson();
    j["intensity_mW_per_mm2"].erase(0);
    CHECK_THROWS_WITH(BeamKernel::fromJson(j, "k.json"), Catch::Contains("rows"));
    std::remove(path.c_str());

    BeamKernel empty;
    CHECK_THROWS_AS(fitKernel(empty), InputError);
    BeamKernel flat = synthetic(0.05, [](double) { return 0.0; });
    CHECK_THROWS_WITH(fitKernel(flat), Catch::Contains("no usable intensity"));
    BeamKernel growing = synthetic(0.05, [](double z) { return 10 + 1000 * z; });
    CHECK_THROWS_WITH(fitKernel(growing), Catch::Contains("cannot fit Eq. 12"));

    transport::McSetup s;
    s.optics.mua = 0.0;
    s.optics.mus = 1.0;
    s.thickness = 0.1;
    s.beam = transport::BeamShape::Gaussian;
    s.photons = 100;
    transport::McResult r = transport::runPhotonMcCpu(s);
    CHECK_THROWS_WITH(kernelFromMonteCarlo(r, 10.0), Catch::Contains("mua > 0"));
}
