// Photon Monte Carlo (CPU path, analog estimator: the other estimators are in
// test_mc_estimators.cpp) against invariants and published values. Statistical checks use
// fixed seeds and bounds of 3-4 standard errors (binomial or batch), so they fail only when the
// physics is wrong, not by chance.

#include <catch2/catch.hpp>

#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/transport/photon_mc.h"

using namespace vpsim;
using namespace vpsim::transport;

namespace {

McSetup hgSlab(double mua, double mus, double g, double thickness, uint64_t photons) {
    McSetup s;
    s.optics.mua = mua;
    s.optics.mus = mus;
    s.optics.g = g;
    s.optics.refractiveIndex = 1.0;
    s.thickness = thickness;
    s.photons = photons;
    s.seed = 12345;
    s.estimator = Estimator::Analog;
    return s;
}

double binomialSigma(double p, uint64_t n) {
    return std::sqrt(std::max(p * (1 - p), 1e-12) / double(n));
}

}  // namespace

TEST_CASE("energy balance is exact in integer weight quanta", "[transport]") {
    // Index mismatch at both faces, scattering, absorption, a lateral bound: every tally is used.
    McSetup s = hgSlab(1.0, 9.0, 0.75, 0.2, 20000);
    s.optics.refractiveIndex = 1.4;
    s.nBelow = 1.5;
    s.lateralRadius = 0.1;
    s.beam = BeamShape::Gaussian;
    s.w0 = 0.05;
    McResult r = runPhotonMcCpu(s);
    BatchTally t = r.total();
    CHECK(t.photons == 20000);
    // Exact integer equality: launched = specular + diffuse + transmitted + absorbed + escaped.
    CHECK(t.photons * r.launchWeight ==
          t.specular + t.diffuse + t.transmitted + t.absorbed + t.escaped);
    CHECK(r.energyBalanced());
    CHECK(t.escaped > 0);
    CHECK(t.transmitted > 0);
    // Bins only hold absorption inside the grid: never more than the absorbed total.
    uint64_t binned = 0;
    for (uint64_t q : r.absorbedRZ) binned += q;
    CHECK(binned <= t.absorbed);
}

TEST_CASE("matched slab reproduces the van de Hulst reflectance and transmittance", "[transport]") {
    // mua = 10/cm, mus = 90/cm, g = 0.75, d = 0.2 mm, n = 1: Rd = 0.09739, Tt = 0.66096
    // (van de Hulst 1980, the MCML validation case). Tolerance: 3 batch standard errors.
    McResult r = runPhotonMcCpu(hgSlab(1.0, 9.0, 0.75, 0.2, 200000));
    INFO("Rd = " << r.diffuse().value << " +- " << r.diffuse().standardError);
    INFO("Tt = " << r.transmitted().value << " +- " << r.transmitted().standardError);
    CHECK(r.specular().value == 0.0);
    CHECK(std::abs(r.diffuse().value - 0.09739) < 3 * r.diffuse().standardError);
    CHECK(std::abs(r.transmitted().value - 0.66096) < 3 * r.transmitted().standardError);
    CHECK(r.diffuse().standardError < 0.002);
    CHECK(r.diffuse().standardError > 0.0);
}

TEST_CASE("semi-infinite isotropic medium reproduces the Chandrasekhar plane albedo",
          "[transport]") {
    // Albedo 0.9, g = 0, matched index, normal incidence: R = 1 - H(1) sqrt(1 - 0.9) = 0.414947
    // with Chandrasekhar's H(1) = 1.850099 (evaluated from its integral form). 4 binomial sigma.
    const uint64_t n = 200000;
    McResult r = runPhotonMcCpu(hgSlab(1.0, 9.0, 0.0, 0.0, n));
    INFO("Rd = " << r.diffuse().value);
    CHECK(std::abs(r.diffuse().value - 0.414947) < 4 * binomialSigma(0.414947, n));
    CHECK(r.transmitted().value == 0.0);
    CHECK(r.diffuse().value + r.absorbed().value == Approx(1.0).margin(1e-12));
}

TEST_CASE("the result summary carries every field of vpsim mc --json", "[transport]") {
    McSetup s = hgSlab(1.0, 9.0, 0.75, 0.2, 1000);
    s.depths = {0.03, 0.084};
    nlohmann::json j = runPhotonMcCpu(s).summaryJson();
    for (const char* key :
         {"photons", "specular_reflectance", "diffuse_reflectance", "transmittance", "absorbed",
          "specular_reflectance_stderr", "diffuse_reflectance_stderr", "transmittance_stderr",
          "absorbed_stderr", "scatterings_per_photon", "photons_per_second", "absorbed_within"})
        CHECK(j.contains(key));
    CHECK(j["absorbed_within"].size() == 2);
    CHECK(j["absorbed_within"][0].get<double>() <= j["absorbed_within"][1].get<double>());
}

TEST_CASE("without scattering the transmittance and absorption follow Beer-Lambert",
          "[transport]") {
    const double mua = 5.0, d = 0.3;
    const uint64_t n = 100000;
    McSetup s = hgSlab(mua, 0.0, 0.0, d, n);
    s.depths = {0.02, 0.1, 0.25};
    McResult r = runPhotonMcCpu(s);
    double t = std::exp(-mua * d);
    // Binomial: each photon is either transmitted or absorbed; 4 sigma.
    CHECK(std::abs(r.transmitted().value - t) < 4 * binomialSigma(t, n));
    CHECK(r.diffuse().value == 0.0);
    CHECK(r.scatteringsPerPhoton() == 0.0);
    for (size_t k = 0; k < s.depths.size(); ++k) {
        double expect = 1 - std::exp(-mua * s.depths[k]);
        INFO("depth " << s.depths[k] << " mm");
        CHECK(std::abs(r.absorbedWithin(k).value - expect) < 4 * binomialSigma(expect, n));
    }
    // Depth profile of the bins: weight absorbed in each z slab ~ exp(-mua z0) - exp(-mua z1).
    s.bins = {1.0, d, 1, 6};
    r = runPhotonMcCpu(s);
    for (uint32_t iz = 0; iz < 6; ++iz) {
        double z0 = d * iz / 6, z1 = d * (iz + 1) / 6;
        double expect = std::exp(-mua * z0) - std::exp(-mua * z1);
        double got = double(r.absorbedRZ[iz]) / double(r.launched());
        CHECK(std::abs(got - expect) < 4 * binomialSigma(expect, n));
    }
}

TEST_CASE("Fresnel: specular reflectance and internal reflection with a mismatched index",
          "[transport]") {
    // Non-absorbing, non-scattering slab n = 1.5 in air: R_sp = 0.04 exactly (to the 2^-24
    // quantum), and multiple reflections give total R = 2R/(1+R) = 0.076923 at normal incidence.
    McSetup s = hgSlab(0.0, 0.0, 0.0, 1.0, 50000);
    s.optics.refractiveIndex = 1.5;
    McResult r = runPhotonMcCpu(s);
    CHECK(r.specular().value == Approx(0.04).margin(1e-7));
    CHECK(r.absorbed().value == 0.0);
    double rTotal = 2 * 0.04 / 1.04;
    CHECK(std::abs(r.specular().value + r.diffuse().value - rTotal) <
          4 * binomialSigma(rTotal - 0.04, 50000));
}

TEST_CASE("white furnace: without absorption all weight is reflected or transmitted",
          "[transport]") {
    McSetup s = hgSlab(0.0, 20.0, 0.9, 0.5, 20000);
    s.optics.refractiveIndex = 1.45;
    McResult r = runPhotonMcCpu(s);
    BatchTally t = r.total();
    CHECK(t.absorbed == 0);
    CHECK(t.escaped == 0);
    CHECK(t.specular + t.diffuse + t.transmitted == r.launched());  // R + T = 1 exactly
    CHECK(r.scatteringsPerPhoton() > 5.0);
}

TEST_CASE("Gaussian beam: unscattered absorption is distributed as exp(-2 r^2 / W0^2)",
          "[transport]") {
    // W0 is the 1/e^2 intensity radius: the power inside r is 1 - exp(-2 r^2 / W0^2).
    const double w0 = 0.05;
    const uint64_t n = 100000;
    McSetup s = hgSlab(20.0, 0.0, 0.0, 0.0, n);  // semi-infinite, strongly absorbing
    s.beam = BeamShape::Gaussian;
    s.w0 = w0;
    s.bins = {0.1, 10.0, 4, 1};
    McResult r = runPhotonMcCpu(s);
    double inner = 0;
    for (uint32_t ir = 0; ir < 4; ++ir) {
        inner += double(r.absorbedRZ[ir]) / double(r.launched());
        double rr = 0.025 * (ir + 1);
        double expect = 1 - std::exp(-2 * rr * rr / (w0 * w0));
        INFO("r = " << rr);
        CHECK(std::abs(inner - expect) < 4 * binomialSigma(expect, n));
    }
}

TEST_CASE("the same seed gives identical tallies on 1 thread and many", "[transport]") {
    McSetup s = hgSlab(1.0, 30.0, 0.8, 0.3, 30000);
    s.beam = BeamShape::Gaussian;
    s.grid = {0.02, 10, 10};
    McResult one = runPhotonMcCpu(s, 1);
    McResult many = runPhotonMcCpu(s, 4);
    for (int b = 0; b < MC_BATCHES; ++b) {
        CHECK(one.batches[b].diffuse == many.batches[b].diffuse);
        CHECK(one.batches[b].absorbed == many.batches[b].absorbed);
        CHECK(one.batches[b].scatterings == many.batches[b].scatterings);
    }
    CHECK(one.absorbedRZ == many.absorbedRZ);
    CHECK(one.absorbedGrid == many.absorbedGrid);
    s.seed += 1;
    McResult other = runPhotonMcCpu(s, 2);
    CHECK(other.total().diffuse != one.total().diffuse);
}

TEST_CASE("tabulated phase function matches Henyey-Greenstein when tabulated from it",
          "[transport]") {
    // Inverse CDF of HG g = 0.75 sampled at 4001 points: the tabulated path must agree with the
    // analytic one within statistics (3 combined standard errors).
    McSetup hg = hgSlab(1.0, 9.0, 0.75, 0.2, 100000);
    McSetup tab = hg;
    tab.optics.phase = optics::PhaseModel::Tabulated;
    const int n = 4001;
    for (int i = 0; i < n; ++i) {
        double u = double(i) / (n - 1);
        double g = 0.75, t = (1 - g * g) / (1 - g + 2 * g * (1 - u));  // u = 0 -> cos = +1
        tab.optics.inverseCdf.push_back(
            float(std::clamp((1 + g * g - t * t) / (2 * g), -1.0, 1.0)));
    }
    tab.seed = 777;
    McResult a = runPhotonMcCpu(hg), b = runPhotonMcCpu(tab);
    auto close = [](Fraction x, Fraction y) {
        return std::abs(x.value - y.value) < 3 * std::hypot(x.standardError, y.standardError);
    };
    CHECK(close(a.diffuse(), b.diffuse()));
    CHECK(close(a.transmitted(), b.transmitted()));
}

TEST_CASE("bad Monte Carlo setups give clear errors", "[transport]") {
    McSetup s = hgSlab(1.0, 9.0, 0.75, 0.2, 100);
    auto expectError = [](McSetup bad, const std::string& part) {
        REQUIRE_THROWS_AS(runPhotonMcCpu(bad), Error);
        try {
            runPhotonMcCpu(bad);
        } catch (const Error& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find(part) != std::string::npos);
        }
    };
    McSetup b = s;
    b.optics.g = 1.0;
    expectError(b, "g");
    b = s;
    b.optics.mua = -1;
    expectError(b, "absorption");
    b = s;
    b.photons = 0;
    expectError(b, "photon");
    b = s;
    b.thickness = 0;
    b.optics.mua = 0;
    expectError(b, "semi-infinite");
    b = s;
    b.beam = BeamShape::Gaussian;
    b.w0 = 0;
    expectError(b, "W0");
    b = s;
    b.optics.phase = optics::PhaseModel::Tabulated;
    expectError(b, "inverse-CDF");
    b = s;
    b.depths = {0.1, 0.1, 0.1, 0.1, 0.1};
    expectError(b, "at most 4");
    b = s;
    b.grid = {0.001, 4096, 4096};
    REQUIRE_THROWS_AS(runPhotonMcCpu(b), ResourceError);
}
