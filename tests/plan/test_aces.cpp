#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/plan/aces.h"
#include "vpsim/plan/dlp_masks.h"

using namespace vpsim;
using namespace vpsim::plan;

// Poisson summation of Eq. C.7: sum_l exp(-2 (y - l rh)^2) has relative harmonics
// 2 exp(-pi^2 k^2 / (2 rh^2)) cos(2 pi k y / rh), so the relative standard deviation is
// sqrt(2) exp(-pi^2 / (2 rh^2)) to within the second harmonic (< 1e-10 relative here): 1e-3.
TEST_CASE("the ACES exposure ripple matches its closed form", "[plan][aces]") {
    for (double rh : {0.8, 1.0, 1.2}) {
        double closedForm = std::sqrt(2.0) * std::exp(-M_PI * M_PI / (2 * rh * rh));
        INFO("rh = " << rh);
        CHECK(acesRipple(rh) == Approx(closedForm).epsilon(1e-3));
    }
    double rh = acesHatchRatio(0.01);
    CHECK(acesRipple(rh) == Approx(0.01).epsilon(1e-6));
    CHECK(rh == Approx(M_PI / std::sqrt(2 * std::log(std::sqrt(2.0) / 0.01))).epsilon(1e-3));
    CHECK_THROWS_AS(acesHatchRatio(0.0), InputError);
}

// For dense lines the half-field tends to 0.5 erfc(sqrt(2) (y - rh/2)) (the field reaches half a
// spacing beyond its last line): the 5% point is at 1.1631/sqrt(2) + rh/2. Tolerance 1e-3 W.
TEST_CASE("the ACES edge offset matches the continuous half-field limit", "[plan][aces]") {
    const double rh = 0.02;  // the discrete sum differs from the integral by O(rh^2)
    CHECK(acesEdgeDistance(rh, 0.05) == Approx(1.16309 / std::sqrt(2.0) + rh / 2).margin(1e-3));
    CHECK(acesEdgeDistance(rh, 0.5) == Approx(rh / 2).margin(1e-3));
}

TEST_CASE("ACES design follows Eq. 14 and Eq. C.9", "[plan][aces]") {
    AcesParameters p;
    p.beamRadius = 0.05;
    p.attenuationLength = 0.12;
    p.depthOfMaximum = 0.01;
    p.criticalDose = 0.1;
    p.layerThickness = 0.05;
    p.laserPower = 10.0;
    p.homogeneity = 0.01;
    auto square = geometry::PolygonSet::rectangle({0, 0}, {2, 1});
    AcesDesign design = designAces(p, square);
    CHECK(design.targetDose == Approx(0.1 * std::exp(0.04 / 0.12)).epsilon(1e-12));
    CHECK(design.speed == Approx(10.0 / (design.targetDose * design.hatchSpacing)).epsilon(1e-12));
    CHECK(design.hatchSpacing <= acesHatchRatio(0.01) * 0.05 + 1e-12);
    CHECK(design.ripple <= 0.01 + 1e-9);
    CHECK(design.direction == Approx(0.0).margin(1e-12));  // the longest edge runs along x
    CHECK(design.edgeOffset ==
          Approx(acesEdgeDistance(acesHatchRatio(0.01), 0.05) * 0.05).epsilon(1e-9));
    p.laserPower = 0;
    CHECK_THROWS_AS(designAces(p, square), InputError);
}

TEST_CASE("hatching clips scan lines to the region and alternates direction", "[plan][aces]") {
    // A 1 x 1 square with a 0.5 x 0.5 hole: 11 lines at 0.1 mm; the 5 through the hole split.
    auto region = geometry::PolygonSet::rectangle({0, 0}, {1, 1})
                      .difference(geometry::PolygonSet::rectangle({0.25, 0.25}, {0.75, 0.75}));
    auto vectors = hatchRegion(region, 0.1, 0.0, 10.0, 100.0);
    double length = 0;
    for (const auto& v : vectors) {
        length += std::hypot(v.x1 - v.x0, v.y1 - v.y0);
        CHECK(std::abs(v.y1 - v.y0) < 1e-9);
        bool throughHole = v.y0 > 0.25 && v.y0 < 0.75;
        CHECK_FALSE((throughHole && std::min(v.x0, v.x1) < 0.7 && std::max(v.x0, v.x1) > 0.3));
    }
    CHECK(length == Approx(11 * 1.0 - 5 * 0.5).epsilon(1e-6));
    for (const auto& v : vectors) {
        long line = std::lround(v.y0 / 0.1);
        INFO("line " << line);
        CHECK((v.x1 > v.x0) == (line % 2 == 0));  // boustrophedon: odd lines run backwards
    }
}

TEST_CASE("uniform DLP masks cover the region with one dose", "[plan][dlp]") {
    auto region = geometry::PolygonSet::rectangle({0, 0}, {1.0, 0.5});
    auto grid = geometry::RasterGrid::covering({0, 0}, {1.0, 0.5}, 0.0625, 2);
    MaskImage binary = uniformMask(region, grid, 0.78);
    MaskImage grey = uniformMask(region, grid, 0.78, MaskRasterMode::Greyscale);
    double energyBinary = 0, energyGrey = 0;
    for (float d : binary.dose) energyBinary += d * 0.0625 * 0.0625;
    for (float d : grey.dose) energyGrey += d * 0.0625 * 0.0625;
    CHECK(energyGrey == Approx(0.78 * 0.5).epsilon(1e-6));
    CHECK(energyBinary == Approx(0.78 * 0.5).epsilon(1e-6));  // edges on pixel boundaries here
    CHECK_THROWS_AS(uniformMask(region, grid, -1.0), InputError);
}
