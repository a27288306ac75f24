// The control variates of the collision and track-length estimators
// (shaders/include/photon_control.glsl, src/transport/mc_control.cpp): every term has mean zero
// on the four reference cases of issue 14 (a nonzero mean would bias the controlled estimates),
// the controlled estimates have the variance reduction they exist for, and the reported
// fractions still add up. Agreement of the controlled estimates with the published values and
// with the analog estimator is in test_mc_estimators.cpp (diffuse() is the controlled estimate).

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "mc_test_support.h"
#include "vpsim/optics/material.h"
#include "vpsim/transport/beam_convolution.h"
#include "vpsim/transport/photon_mc.h"

using namespace vpsim;
using namespace vpsim::transport;
using vpsim::test::agree;

namespace {

McSetup medium(double mua, double mus, double g, double n, double thickness, uint64_t photons) {
    return vpsim::test::hgSetup(mua, mus, g, n, thickness, photons, 977);
}

McSetup seed000Slurry(uint64_t photons) {
    McSetup s;
    s.optics =
        optics::loadMediumOptics(VPSIM_SOURCE_DIR "/examples/materials/alumina-seed000.json");
    s.photons = photons;
    s.seed = 977;
    return s;
}

/// Every control term's mean per photon, in standard errors of the control batches' spread.
void checkTermsHaveMeanZero(const McResult& r) {
    REQUIRE(r.controlBatches.size() == size_t(MC_CONTROL_BATCHES));
    for (int t = 0; t < MC_CONTROL_TERMS; ++t) {
        double sum = 0, squares = 0;
        for (const ControlTally& c : r.controlBatches) {
            const double v = std::ldexp(double(c.controls[size_t(t)]), -32);
            sum += v;
            squares += v * v;
        }
        const double n = MC_CONTROL_BATCHES;
        const double spread = std::sqrt(std::max(squares / n - (sum / n) * (sum / n), 0.0) * n);
        INFO("term " << t << ": sum " << sum << " spread " << spread);
        // 10 terms x 4 cases: 4.5 sigma keeps chance failures below 1e-4 in all.
        CHECK(std::abs(sum) <= 4.5 * spread + 1e-6);
    }
}

}  // namespace

TEST_CASE("control terms have mean zero on the four reference cases", "[transport][control]") {
    for (Estimator e : {Estimator::Collision, Estimator::Track}) {
        INFO(estimatorName(e));
        McSetup hulst = medium(1.0, 9.0, 0.75, 1.0, 0.2, 100000);  // van de Hulst's slab
        McSetup giovanelli = medium(1.0, 9.0, 0.75, 1.5, 0.0, 100000);
        McSetup slurry = medium(8.4, 303.0, 0.9, 1.0, 0.0, 60000);
        McSetup mie = seed000Slurry(60000);
        for (McSetup* s : {&hulst, &giovanelli, &slurry, &mie}) {
            s->estimator = e;
            const McResult r = runPhotonMcCpu(*s);
            INFO("n " << s->optics.refractiveIndex << " thickness " << s->thickness);
            checkTermsHaveMeanZero(r);
        }
    }
}

TEST_CASE("controlled reflectance has less variance than the tally", "[transport][control]") {
    // Slurry-like HG medium, matched boundary: measured 15x less variance (bench_photon_mc);
    // with a refractive step (n = 1.45 inside) total internal reflection leaves about 2x.
    McSetup matched = medium(8.4, 303.0, 0.9, 1.0, 0.0, 200000);
    McResult a = runPhotonMcCpu(matched);
    INFO("matched: controlled " << a.diffuse().standardError << " tally "
                                << a.diffuseTally().standardError);
    CHECK(a.diffuse().standardError < 0.4 * a.diffuseTally().standardError);
    CHECK(agree(a.diffuse(), a.diffuseTally()));
    McSetup step = medium(8.4, 303.0, 0.9, 1.45, 0.0, 200000);
    McResult b = runPhotonMcCpu(step);
    INFO("n 1.45: controlled " << b.diffuse().standardError << " tally "
                               << b.diffuseTally().standardError);
    CHECK(b.diffuse().standardError < 0.85 * b.diffuseTally().standardError);
    CHECK(agree(b.diffuse(), b.diffuseTally()));
    // The depth tallies share the terms (they are tied to the reflectance by the balance).
    McSetup depths = matched;
    depths.depths = {0.03, 0.084};
    McResult c = runPhotonMcCpu(depths);
    for (size_t k = 0; k < 2; ++k) {
        INFO("depth " << k << ": controlled " << c.absorbedWithin(k).standardError << " tally "
                      << c.absorbedWithinTally(k).standardError);
        CHECK(c.absorbedWithin(k).standardError < c.absorbedWithinTally(k).standardError);
        CHECK(agree(c.absorbedWithin(k), c.absorbedWithinTally(k)));
    }
}

TEST_CASE("controlled fractions add up and survive the beam convolution", "[transport][control]") {
    // absorbed() is what the controlled reflectance and transmittance leave, so the reported
    // fractions sum to 1 as the integer tallies do; a Gaussian beam traced as a convolved pencil
    // keeps the control batches.
    McSetup s = medium(1.0, 9.0, 0.75, 1.5, 0.2, 50000);
    s.beam = BeamShape::Gaussian;
    s.w0 = 0.05;
    s.bins = {0.4, 0.2, 40, 10};
    McResult r = runPhotonMcCpu(s);
    REQUIRE(convolvesBeam(s));
    REQUIRE(r.controlBatches.size() == size_t(MC_CONTROL_BATCHES));
    CHECK(r.energyBalanced());
    CHECK(r.specular().value + r.diffuse().value + r.transmitted().value + r.absorbed().value ==
          Approx(1.0).margin(1e-12));
    CHECK(r.diffuse().standardError < r.diffuseTally().standardError);
    CHECK(agree(r.diffuse(), r.diffuseTally()));
    CHECK(agree(r.transmitted(), r.transmittedTally()));
    // Switched off: the same integer tallies and bins (the controls draw no random number), the
    // plain estimates, no control batches.
    McSetup plain = s;
    plain.controlVariates = false;
    McResult p = runPhotonMcCpu(plain);
    CHECK_FALSE(p.controlled());
    CHECK(p.controlBatches.empty());
    CHECK(p.total().diffuse == r.total().diffuse);
    CHECK(p.total().absorbed == r.total().absorbed);
    CHECK(p.absorbedRZ == r.absorbedRZ);
    CHECK(p.diffuse().value == r.diffuseTally().value);
    // The analog estimator reports its plain tallies.
    s.estimator = Estimator::Analog;
    McResult a = runPhotonMcCpu(s);
    CHECK_FALSE(a.controlled());
    CHECK(a.controlBatches.empty());
    CHECK(a.diffuse().value == a.diffuseTally().value);
}
