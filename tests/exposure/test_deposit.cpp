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
