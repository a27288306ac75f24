#include <catch2/catch.hpp>

#include "vpsim/exposure/deposit.h"

using namespace vpsim;
using namespace vpsim::exposure;

// Deposits conserve energy exactly (up to float rounding of the per-cell sums, 1e-6 relative):
// a vector delivers power x length / speed, a point its energy, a mask dose x pixel area.
TEST_CASE("deposits conserve the energy of vectors points and masks", "[exposure]") {
    SurfaceGrid grid(200, 200, -1.0, -1.0, 0.01);
    plan::LayerPlan layer;
    layer.vectors.push_back(
        {-0.7, -0.3, 0.55, 0.61, 12.0, 300.0});  // oblique: crosses cells both ways
    layer.points.push_back({0.123, -0.456, 0.02});
    plan::MaskImage mask;
    mask.width = 4;
    mask.height = 3;
    mask.originX = 0.2;
    mask.originY = 0.3;
    mask.pixelPitch = 0.0625;  // not a multiple of the grid pitch: exact overlaps are needed
    mask.dose.assign(12, 0.5f);
    layer.masks.push_back(mask);
    depositLayer(layer, grid);
    double expected = 12.0 * std::hypot(1.25, 0.91) / 300.0 + 0.02 + 0.5 * 12 * 0.0625 * 0.0625;
    CHECK(grid.totalEnergy() == Approx(expected).epsilon(1e-6));
}

TEST_CASE("a vector deposits only in the cells along its path", "[exposure]") {
    SurfaceGrid grid(10, 10, 0.0, 0.0, 1.0);
    plan::LayerPlan layer;
    layer.vectors.push_back({0.5, 2.5, 7.5, 2.5, 1.0, 1.0});
    depositLayer(layer, grid);
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i) {
            double expected = j != 2 ? 0.0 : (i == 0 || i == 7) ? 0.5 : (i < 7 ? 1.0 : 0.0);
            CHECK(grid.at(i, j) == Approx(expected).margin(1e-6));
        }
}

namespace {

/// Every sample of every vector splatted in plan order by one loop over the whole grid: what
/// the row bands of depositLayer must reproduce bit for bit (same additions, same order).
SurfaceGrid serialDeposit(const plan::LayerPlan& layer, SurfaceGrid grid) {
    for (const auto& v : layer.vectors) {
        const double length = std::hypot(v.x1 - v.x0, v.y1 - v.y0);
        const long samples = std::max(1L, long(std::ceil(length / (0.25 * grid.pitch))));
        const double energy = v.power / v.speed * length / double(samples);
        for (long s = 0; s < samples; ++s) {
            const double t = (s + 0.5) / double(samples);
            const double x = v.x0 + t * (v.x1 - v.x0), y = v.y0 + t * (v.y1 - v.y0);
            const double fx = (x - grid.originX) / grid.pitch - 0.5,
                         fy = (y - grid.originY) / grid.pitch - 0.5;
            const int i = int(std::floor(fx)), j = int(std::floor(fy));
            const double ax = fx - i, ay = fy - j;
            const double perArea = energy / (grid.pitch * grid.pitch);
            const double w[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
            for (int k = 0; k < 4; ++k) {
                const int ii = i + (k & 1) - grid.firstI, jj = j + (k >> 1) - grid.firstJ;
                if (ii >= 0 && jj >= 0 && ii < grid.nx && jj < grid.ny)
                    grid.at(ii, jj) += float(perArea * w[k]);
            }
        }
    }
    return grid;
}

}  // namespace

TEST_CASE("row bands deposit slanted and vertical vectors exactly as one serial pass",
          "[exposure]") {
    plan::LayerPlan layer;
    layer.vectors.push_back({0.013, 0.004, 0.017, 2.991, 10.0, 400.0});  // near vertical, up
    layer.vectors.push_back({1.5, 2.9, 1.5, 0.1, 10.0, 400.0});          // vertical, down
    layer.vectors.push_back({0.1, 0.2, 2.8, 2.7, 10.0, 400.0});          // diagonal
    layer.vectors.push_back({2.9, 1.0, 0.05, 1.0000001, 10.0, 400.0});   // almost horizontal
    layer.vectors.push_back({0.3, 1.2345, 2.7, 1.2345, 10.0, 400.0});    // horizontal
    layer.vectors.push_back({-0.5, -0.5, 3.5, 3.2, 10.0, 400.0});        // leaves the grid
    SECTION("the whole grid") {
        SurfaceGrid grid(300, 300, 0.0, 0.0, 0.01);
        const SurfaceGrid expected = serialDeposit(layer, grid);
        depositLayer(layer, grid);
        CHECK(grid.values == expected.values);
    }
    SECTION("a window of it (a tile)") {
        SurfaceGrid grid(120, 170, 0.0, 0.0, 0.01);
        grid.firstI = 90;
        grid.firstJ = 65;
        const SurfaceGrid expected = serialDeposit(layer, grid);
        depositLayer(layer, grid);
        CHECK(grid.values == expected.values);
    }
}
