#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/plan/feature_blocks.h"

using namespace vpsim;
using namespace vpsim::plan;

// Reff is where a Gaussian dot falls to 1% of its centre: exp(-2 Reff^2 / W^2) = 0.01.
TEST_CASE("the effective radius is the 1% radius of a dot", "[plan][dfbtp]") {
    double w = 0.05, reff = effectiveRadius(w);
    CHECK(std::exp(-2 * reff * reff / (w * w)) == Approx(0.01).epsilon(1e-12));
}

// Seed 000 Fig. 17 on a polygon with a hole: a 2 x 2 mm square with a 0.8 mm square hole has 8
// straight edges and 8 corners (4 convex on the outside, 4 concave around the hole); each
// edge's sub-blocks are bands of Reff, Roff and Reff across the edge over its length minus the
// corner blocks, sub-block 2 lies inside the region and outside the middle area, sub-block 1
// outside the region. Tolerance: Clipper's 1 nm rounding (1e-6 mm^2).
TEST_CASE("features of a polygon with a hole", "[plan][dfbtp]") {
    auto region = geometry::PolygonSet::rectangle({0, 0}, {2, 2})
                      .difference(geometry::PolygonSet::rectangle({0.6, 0.6}, {1.4, 1.4}));
    const double roff = 0.06, w = 0.05, reff = effectiveRadius(w), half = roff + w;
    FeatureBlocks b = disassembleFeatures(region, roff, reff, w);
    CHECK(b.middle.area() == Approx(region.offset(-roff).area()).epsilon(1e-9));
    REQUIRE(b.edges.size() == 8);
    REQUIRE(b.corners.size() == 8);
    int convex = 0;
    for (const auto& c : b.corners) convex += c.convex;
    CHECK(convex == 4);
    for (const auto& e : b.edges) {
        double length = std::hypot(e.b.x - e.a.x, e.b.y - e.a.y) - 2 * half;
        CHECK(e.sub[0].area() == Approx(length * reff).margin(1e-6));
        CHECK(e.sub[1].area() == Approx(length * roff).margin(1e-6));
        CHECK(e.sub[2].area() == Approx(length * reff).margin(1e-6));
        CHECK(e.sub[1].difference(region).area() < 1e-6);      // inside the region
        CHECK(e.sub[1].intersection(b.middle).area() < 1e-6);  // outside the middle area
        CHECK(e.sub[0].intersection(region).area() < 1e-6);    // outside the region
        // The inward normal points into the region.
        glm::dvec2 mid = 0.5 * (e.a + e.b) + 0.01 * e.normal;
        CHECK(region.contains(mid));
    }
    for (const auto& c : b.corners) {
        CHECK(c.sub[0].area() + c.sub[2].area() ==
              Approx(c.square.intersection(region).area()).margin(1e-6));
        CHECK(c.sub[1].intersection(region).area() < 1e-6);
    }
    CHECK_THROWS_AS(disassembleFeatures(region, 0, reff, w), InputError);
}

// A polygonised circle has no corners (turns below 0.2 rad) and no straight edges longer than
// two corner blocks: only the middle area; the inverse planner handles such curves.
TEST_CASE("a polygonised circle is all middle area", "[plan][dfbtp]") {
    geometry::Contour c;
    for (int i = 0; i < 64; ++i)
        c.push_back({std::cos(2 * M_PI * i / 64), std::sin(2 * M_PI * i / 64)});
    FeatureBlocks b = disassembleFeatures(geometry::PolygonSet::fromContours({c}), 0.06,
                                          effectiveRadius(0.05), 0.05);
    CHECK(b.corners.empty());
    CHECK(b.edges.empty());
    CHECK(b.middle.area() == Approx(M_PI * 0.94 * 0.94).epsilon(0.01));  // the circle less Roff
}
