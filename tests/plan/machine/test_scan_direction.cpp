// Seed 002's scan-direction rule (minimum sum of edge projections, tried on edge directions only)
// against an exhaustive search over angles, on rectangles and L shapes.
#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/plan/aces/aces.h"
#include "vpsim/plan/machine/build_time.h"
#include "vpsim/plan/machine/scan_direction.h"
#include "vpsim/plan/machine/trajectory.h"

using namespace vpsim;
using namespace vpsim::plan;
using geometry::PolygonSet;

namespace {

PolygonSet lShape() {
    return PolygonSet::fromContours({{{0, 0}, {8, 0}, {8, 2}, {2, 2}, {2, 5}, {0, 5}}});
}

/// Distance between two directions modulo pi.
double angleGap(double a, double b) {
    double d = std::fmod(std::abs(a - b), M_PI);
    return std::min(d, M_PI - d);
}

}  // namespace

TEST_CASE("the edge-projection rule finds the exhaustive minimum", "[plan]") {
    for (double tilt : {0.0, 0.3, 1.1, 2.5}) {
        for (const PolygonSet& shape :
             {PolygonSet::rectangle({0, 0}, {10, 2}).rotated(tilt, {5, 1}),
              lShape().rotated(tilt, {1, 1})}) {
            const double rule = scanDirection(shape, {});
            const double ruleSum = edgeProjectionSum(shape, rule);
            double bestSum = INFINITY;
            for (int k = 0; k < 3600; ++k)
                bestSum = std::min(bestSum, edgeProjectionSum(shape, k * M_PI / 3600.0));
            INFO("tilt " << tilt << " area " << shape.area());
            CHECK(ruleSum <= bestSum + 1e-9);
            // Vector counts of the hatching itself: the rule is within one vector of the best of
            // 180 directions.
            const double spacing = 0.05;
            size_t ruleCount = hatchRegion(shape, spacing, rule, 10, 100).size(), bestCount = ~0u;
            for (int k = 0; k < 180; ++k)
                bestCount = std::min(bestCount,
                                     hatchRegion(shape, spacing, k * M_PI / 180.0, 10, 100).size());
            CHECK(ruleCount <= bestCount + 1);
        }
        // A bar is scanned along its length.
        CHECK(angleGap(scanDirection(PolygonSet::rectangle({0, 0}, {10, 2}).rotated(tilt), {}),
                       tilt) < 1e-6);  // Clipper rounds vertices to 1 nm
    }
}

TEST_CASE("the direction rule saves build time on a long bar at an angle", "[plan]") {
    const double tilt = 0.5;
    const PolygonSet bar = PolygonSet::rectangle({0, 0}, {8, 1}).rotated(tilt, {4, 0.5});
    BuildTimeOptions options;
    auto timeAt = [&](double direction) {
        LayerPlan layer;
        layer.vectors = hatchRegion(bar, 0.05, direction, 10, 300);
        LayerTrajectory t = buildLayerTrajectory(layer, 10, TrajectoryOptions{});
        return layerMoveTime(t.moves, options).total();
    };
    const double rule = timeAt(scanDirection(bar, {})), fixed = timeAt(0.0);
    CHECK(rule < 0.8 * fixed);
    CHECK(timeAt(scanDirection(bar, parseDirectionRule("longest-edge"))) == Approx(rule));
}

TEST_CASE("plan.direction values", "[plan]") {
    CHECK(parseDirectionRule("min-edge-projection").kind == DirectionRule::Kind::MinEdgeProjection);
    DirectionRule fixed = parseDirectionRule("30 deg");
    CHECK(fixed.kind == DirectionRule::Kind::Fixed);
    CHECK(fixed.angle == Approx(M_PI / 6));
    CHECK(scanDirection(lShape(), fixed) == Approx(M_PI / 6));
    CHECK(parseDirectionRule("190 deg").angle == Approx(M_PI / 18));
    CHECK(toString(fixed) == "30 deg");
    CHECK_THROWS_WITH(parseDirectionRule("diagonal", "plan.direction", "job.json"),
                      Catch::Contains("plan.direction") && Catch::Contains("job.json"));
}

TEST_CASE("each part hatched along its own direction takes fewer vectors", "[plan]") {
    // A horizontal and a vertical bar: one layer direction suits only one of them.
    const PolygonSet layer =
        PolygonSet::rectangle({0, 0}, {6, 1}).unite(PolygonSet::rectangle({8, 0}, {9, 6}));
    const auto perPart = hatchPartsByRule(layer, 0.05, {}, 10, 300);
    const auto fixed = hatchRegion(layer, 0.05, 0.0, 10, 300);
    CHECK(perPart.size() < 0.6 * fixed.size());
    // Same direction for both: the same count up to where each part's first line falls.
    CHECK(double(hatchPartsByRule(layer, 0.05, parseDirectionRule("0 deg"), 10, 300).size()) ==
          Approx(double(fixed.size())).margin(2));
}
