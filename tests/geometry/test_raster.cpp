// Rasters: exact coverage sums to the polygon area, known partial pixels, binary masks agree with
// point-in-polygon, signed distances match the analytic distance to a square.
#include <catch2/catch.hpp>

#include <cmath>
#include <numeric>

#include "vpsim/geometry/raster.h"
#include "vpsim/geometry/slicer.h"
#include "vpsim/geometry/test_parts.h"

using namespace vpsim::geometry;

namespace {

double coveredArea(const PolygonSet& region, const RasterGrid& grid) {
    const auto coverage = rasterizeCoverage(region, grid);
    return std::accumulate(coverage.begin(), coverage.end(), 0.0) * grid.pitch * grid.pitch;
}

}  // namespace

TEST_CASE("coverage of a square offset from the pixel grid is exact per pixel", "[raster]") {
    const PolygonSet square = PolygonSet::rectangle({0.25, 0.25}, {1.75, 1.5});
    RasterGrid grid;
    grid.pitch = 1.0;
    grid.width = grid.height = 3;
    const auto c = rasterizeCoverage(square, grid);
    // Tolerance 1e-12: only rounding in the accumulation.
    CHECK(c[0] == Approx(0.75 * 0.75).margin(1e-12));
    CHECK(c[1] == Approx(0.75 * 0.75).margin(1e-12));
    CHECK(c[3] == Approx(0.75 * 0.5).margin(1e-12));
    CHECK(c[4] == Approx(0.75 * 0.5).margin(1e-12));
    CHECK(c[2] == Approx(0.0).margin(1e-12));
    CHECK(c[8] == Approx(0.0).margin(1e-12));
}

TEST_CASE("coverage sums equal polygon areas to 1e-9", "[raster]") {
    // Regions with slanted edges, holes, islands and many vertices; grids with odd pitches and
    // origins not aligned to any vertex. Relative tolerance 1e-9 (double accumulation).
    std::vector<PolygonSet> regions;
    TestPartOptions o;
    o.segments = 97;
    regions.push_back(sliceAt(makeTestPart("cylinder", o), 3.3));
    regions.push_back(sliceAt(makeTestPart("tapered"), 4.321));
    regions.push_back(sliceAt(makeTestPart("l-shape"), 1.0));
    regions.push_back(PolygonSet::rectangle({0, 0}, {10, 10})
                          .difference(PolygonSet::fromContours({{{2, 2.5}, {8.3, 3}, {5, 8.7}}}))
                          .unite(PolygonSet::fromContours({{{4.6, 4.5}, {5.4, 4.6}, {5, 5.3}}})));
    for (const double pitch : {0.0137, 0.1, 0.7}) {
        for (const auto& region : regions) {
            const auto [lo, hi] = region.bounds();
            const RasterGrid grid = RasterGrid::covering(lo, hi, pitch, 3);
            INFO("pitch " << pitch << " area " << region.area());
            CHECK(coveredArea(region, grid) == Approx(region.area()).epsilon(1e-9));
            const auto c = rasterizeCoverage(region, grid);
            CHECK(*std::min_element(c.begin(), c.end()) >= 0.0);
            CHECK(*std::max_element(c.begin(), c.end()) <= 1.0);
        }
    }
}

TEST_CASE("a grid cutting through the region covers only its inside part", "[raster]") {
    const PolygonSet square = PolygonSet::rectangle({-1, -1}, {1, 1});
    RasterGrid grid;
    grid.origin = {0.0, -0.5};
    grid.pitch = 0.25;
    grid.width = 8;   // x 0..2
    grid.height = 2;  // y -0.5..0
    CHECK(coveredArea(square, grid) == Approx(1.0 * 0.5).epsilon(1e-12));
}

TEST_CASE("binary mask marks pixel centres inside", "[raster]") {
    const PolygonSet region =
        sliceAt(makeTestPart("l-shape"), 1.0)
            .difference(PolygonSet::fromContours({{{-3.3, -3.1}, {-1.2, -3.4}, {-2.0, -0.7}}}));
    const auto [lo, hi] = region.bounds();
    const RasterGrid grid = RasterGrid::covering(lo, hi, 0.173, 2);
    const auto mask = rasterizeBinary(region, grid);
    size_t mismatches = 0;
    for (int j = 0; j < grid.height; ++j) {
        for (int i = 0; i < grid.width; ++i) {
            mismatches += mask[size_t(j) * grid.width + i] !=
                          uint8_t(region.contains(grid.pixelCentre(i, j)));
        }
    }
    CHECK(mismatches == 0);  // no centre lies on an edge with this pitch
    const double count = double(std::accumulate(mask.begin(), mask.end(), size_t(0)));
    // Centre sampling: area error bounded by perimeter x pitch.
    CHECK(std::abs(count * grid.pitch * grid.pitch - region.area()) <
          region.perimeter() * grid.pitch);
}

TEST_CASE("target map distances match the analytic distance to a square", "[raster]") {
    const PolygonSet square = PolygonSet::rectangle({0, 0}, {2, 2});
    const RasterGrid grid = RasterGrid::covering({0, 0}, {2, 2}, 0.05, 10);
    const double band = 0.3;
    const TargetMap map = makeTargetMap(square, grid, band);
    for (int j = 0; j < grid.height; ++j) {
        for (int i = 0; i < grid.width; ++i) {
            const glm::dvec2 p = grid.pixelCentre(i, j);
            const double dx = std::max({-p.x, p.x - 2.0, 0.0}),
                         dy = std::max({-p.y, p.y - 2.0, 0.0});
            const bool inside = p.x > 0 && p.x < 2 && p.y > 0 && p.y < 2;
            const double exact =
                inside ? -std::min({p.x, 2 - p.x, p.y, 2 - p.y}) : std::hypot(dx, dy);
            const double expected = std::clamp(exact, -band, band);
            // float storage: 1e-6 mm.
            REQUIRE(map.signedDistance[size_t(j) * grid.width + i] ==
                    Approx(expected).margin(1e-6));
        }
    }
}

TEST_CASE("pixel centres exactly on edges follow the half-open rule", "[raster][robust]") {
    // Square [0,1]^2, pitch 0.5, centres at x, y = 0, 0.5, 1, 1.5: the left/bottom edges include
    // their centres, the right/top ones exclude them, so 2 x 2 pixels = area / pitch^2.
    RasterGrid grid;
    grid.origin = {-0.25, -0.25};
    grid.pitch = 0.5;
    grid.width = grid.height = 4;
    const auto mask = rasterizeBinary(PolygonSet::rectangle({0, 0}, {1, 1}), grid);
    CHECK(std::accumulate(mask.begin(), mask.end(), 0) == 4);
    CHECK(mask[0 * 4 + 0] == 1);  // centre (0, 0): on the bottom-left corner, included
    CHECK(mask[1 * 4 + 1] == 1);  // centre (0.5, 0.5)
    CHECK(mask[2 * 4 + 2] == 0);  // centre (1, 1): on the top-right corner, excluded
    CHECK(mask[0 * 4 + 2] == 0);  // centre (1, 0): on the right edge, excluded
    CHECK(mask[2 * 4 + 0] == 0);  // centre (0, 1): on the top edge, excluded
}
