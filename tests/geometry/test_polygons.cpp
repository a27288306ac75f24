// PolygonSet: areas, orientation, booleans and offsets against closed-form values.
// Tolerance: coordinates are rounded to 1 nm, so areas agree to (perimeter x 1e-6 mm).
#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/geometry/polygons.h"

using namespace vpsim::geometry;

namespace {
constexpr double PI = 3.14159265358979323846;
const PolygonSet SQUARE = PolygonSet::rectangle({0, 0}, {10, 10});
}  // namespace

TEST_CASE("rectangle area, perimeter, orientation, containment", "[polygons]") {
    CHECK(SQUARE.area() == Approx(100.0).epsilon(1e-15));
    CHECK(SQUARE.perimeter() == Approx(40.0).epsilon(1e-15));
    CHECK(signedArea(SQUARE.parts().at(0).outer) > 0.0);
    CHECK(SQUARE.contains({5, 5}));
    CHECK(SQUARE.contains({10, 5}));  // boundary counts as inside
    CHECK_FALSE(SQUARE.contains({10.001, 5}));
}

TEST_CASE("clockwise input is normalised to a counter-clockwise outer", "[polygons]") {
    const PolygonSet set = PolygonSet::fromContours({{{0, 0}, {0, 2}, {2, 2}, {2, 0}}});
    REQUIRE(set.outerCount() == 1);
    CHECK(signedArea(set.parts()[0].outer) == Approx(4.0));
}

TEST_CASE("booleans of overlapping squares", "[polygons]") {
    const PolygonSet other = PolygonSet::rectangle({5, 5}, {15, 15});
    CHECK(SQUARE.unite(other).area() == Approx(175.0).epsilon(1e-12));
    CHECK(SQUARE.intersection(other).area() == Approx(25.0).epsilon(1e-12));
    CHECK(SQUARE.difference(other).area() == Approx(75.0).epsilon(1e-12));
    CHECK(SQUARE.unite(other).outerCount() == 1);
}

TEST_CASE("difference makes a clockwise hole; nested islands stay separate outers", "[polygons]") {
    const PolygonSet ring = SQUARE.difference(PolygonSet::rectangle({2, 2}, {8, 8}));
    REQUIRE(ring.outerCount() == 1);
    REQUIRE(ring.holeCount() == 1);
    CHECK(signedArea(ring.parts()[0].holes[0]) == Approx(-36.0));
    CHECK(ring.area() == Approx(64.0));
    CHECK_FALSE(ring.contains({5, 5}));
    const PolygonSet withIsland = ring.unite(PolygonSet::rectangle({4, 4}, {6, 6}));
    CHECK(withIsland.outerCount() == 2);
    CHECK(withIsland.holeCount() == 1);
    CHECK(withIsland.area() == Approx(68.0));
    CHECK(withIsland.contains({5, 5}));
}

TEST_CASE("offsets of a square", "[polygons]") {
    // Miter: exactly the larger square. Round: square + side strips + a full circle of radius d,
    // whose chords (arc tolerance 1 um) lose at most 2 pi d x 1 um of area.
    const double d = 1.0;
    CHECK(SQUARE.offset(d, JoinType::Miter).area() == Approx(144.0).epsilon(1e-12));
    const double round = 100.0 + 40.0 * d + PI * d * d;
    CHECK(std::abs(SQUARE.offset(d, JoinType::Round).area() - round) < 2.0 * PI * d * 1e-3);
    CHECK(SQUARE.offset(-d).area() == Approx(64.0).epsilon(1e-12));  // inward offset keeps corners
    CHECK(SQUARE.offset(-6.0).empty());                              // shrinks away
}

TEST_CASE("translation moves the region", "[polygons]") {
    const PolygonSet moved = SQUARE.translated({1.5, -2.0});
    const auto [lo, hi] = moved.bounds();
    CHECK(lo.x == Approx(1.5));
    CHECK(hi.y == Approx(8.0));
    CHECK(moved.area() == Approx(100.0));
}

TEST_CASE("scanline intervals and rotation", "[polygons]") {
    const PolygonSet ring = SQUARE.difference(PolygonSet::rectangle({2, 2}, {8, 8}));
    const auto through = ring.intervalsAt(5.0);
    REQUIRE(through.size() == 2);
    CHECK(through[0].first == Approx(0.0));
    CHECK(through[0].second == Approx(2.0));
    CHECK(through[1].first == Approx(8.0));
    CHECK(through[1].second == Approx(10.0));
    REQUIRE(ring.intervalsAt(1.0).size() == 1);
    CHECK(ring.intervalsAt(1.0)[0].second == Approx(10.0));
    CHECK(ring.intervalsAt(10.0).empty());     // top edge: half-open, excluded
    CHECK(ring.intervalsAt(0.0).size() == 1);  // bottom edge: included
    // A diamond (square rotated 45 degrees about its centre): width 2 (r - |y - 5|) at height y.
    const PolygonSet diamond = SQUARE.rotated(0.25 * PI, {5, 5});
    CHECK(diamond.area() == Approx(100.0).margin(40.0 * 1e-6));  // vertices re-rounded to 1 nm
    const double r = 5.0 * std::sqrt(2.0);
    const auto row = diamond.intervalsAt(6.0);
    REQUIRE(row.size() == 1);
    CHECK(row[0].second - row[0].first == Approx(2.0 * (r - 1.0)).margin(4e-6));
    CHECK(signedArea(diamond.parts()[0].outer) > 0.0);
}
