#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/plan/aces/aces.h"

using namespace vpsim;
using namespace vpsim::plan;

namespace {

AcesParameters contourParameters() {
    AcesParameters p;
    p.beamRadius = 0.05;
    p.attenuationLength = 0.1;  // print-through matters: a layer passes exp(-0.5) = 0.61
    p.layerThickness = 0.05;
    p.edge = AcesEdge::CureAtContour;
    return p;
}

const double RH = 1.0;  // hatch ratio of the tests' designs

}  // namespace

// The stack-aware rule against the closed-form ones it generalises, on a 2 mm square whose
// corners are a small part of the contour. Tolerance 0.01 W: the tabulated profile (0.005 W
// steps), the wall grid (W/64 steps) and 8 against 32 depth samples.
TEST_CASE("the stack-aware contour rule reduces to the steady and single-layer rules",
          "[plan][aces]") {
    const AcesParameters p = contourParameters();
    const double W = p.beamRadius, q = std::exp(-p.layerThickness / p.attenuationLength);
    const double etar = acesTargetDose(p.criticalDose, p.layerThickness, 0, p.attenuationLength);
    const double fraction = p.criticalDose / etar, depth = p.layerThickness / p.attenuationLength;
    const auto square = geometry::PolygonSet::rectangle({0, 0}, {2, 2});
    SECTION("nothing around: the single-layer rule") {
        double single = acesContourDistance(RH, fraction, depth, 1.0) * W;
        CHECK(acesStackContourOffset(p, square, RH, etar, {}) == Approx(single).margin(0.01 * W));
    }
    SECTION("identical layers above with the steady offset: the steady rule") {
        double steady = acesContourDistance(RH, fraction, depth, 1.0 / (1.0 - q)) * W;
        AcesStack stack;
        for (int j = 1; j <= 20; ++j)  // q^20 = 5e-5 of the own exposure is left out
            stack.above.push_back({&square, j * p.layerThickness, steady});
        stack.below = AcesNeighbour{&square, p.layerThickness, 0.0};
        CHECK(acesStackContourOffset(p, square, RH, etar, stack) ==
              Approx(steady).margin(0.01 * W));
    }
}

// A taper's narrower layers above send little to the wall (the own field must reach out: a
// smaller offset than under identical layers); an overhang's wider layers send a lot (a larger
// offset, up to the 3 W bound).
TEST_CASE("the stack-aware contour rule follows the layers above", "[plan][aces]") {
    const AcesParameters p = contourParameters();
    const double etar = acesTargetDose(p.criticalDose, p.layerThickness, 0, p.attenuationLength);
    const auto square = geometry::PolygonSet::rectangle({0, 0}, {2, 2});
    auto offsetUnder = [&](double stepPerLayer) {
        std::vector<geometry::PolygonSet> above;
        for (int j = 1; j <= 10; ++j) above.push_back(square.offset(-j * stepPerLayer));
        AcesStack stack;
        for (int j = 1; j <= 10; ++j)
            stack.above.push_back({&above[j - 1], j * p.layerThickness, 0.03});
        return acesStackContourOffset(p, square, RH, etar, stack);
    };
    const double straight = offsetUnder(0.0);
    CHECK(offsetUnder(0.025) < straight);
    CHECK(offsetUnder(-0.025) > straight);
    CHECK(offsetUnder(-0.025) <= 3 * p.beamRadius + 1e-12);
    CHECK(acesStackContourOffset(p, square, RH, etar, {}) < offsetUnder(0.025));
}
