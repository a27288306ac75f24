#include <catch2/catch.hpp>

#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/plan/aces/aces.h"

using namespace vpsim;

// End to end through the planner and the engine: an ACES design exposes the middle of a region at
// its target dose Etar (Eq. C.8/C.9), within the design's ripple (1%) plus the grid's 0.5%.
TEST_CASE("an ACES plan exposes the middle of the region at the target dose", "[exposure][aces]") {
    plan::AcesParameters p;
    p.beamRadius = 0.05;
    p.attenuationLength = 0.12;
    p.criticalDose = 0.1;
    p.layerThickness = 0.05;
    p.laserPower = 10.0;
    p.homogeneity = 0.01;
    auto region = geometry::PolygonSet::rectangle({0, 0}, {1.2, 0.8});
    plan::AcesDesign design = plan::designAces(p, region);
    plan::LayerPlan layer = plan::planAcesLayer(region, design, p.laserPower, 0.05);
    REQUIRE(!layer.vectors.empty());

    exposure::ExposureGrid grid = exposure::ExposureGrid::covering(0, 0, 1.2, 0.8, 0.15, 0.005, 1);
    exposure::ExposureEngine engine(grid, {p.beamRadius, p.attenuationLength}, p.layerThickness);
    exposure::SurfaceGrid deposit(grid.nx, grid.ny, grid.originX, grid.originY, grid.pitch);
    exposure::depositLayer(layer, deposit);
    exposure::SurfaceGrid map = engine.exposureMap(deposit);
    for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i) {
            double x = map.centreX(i), y = map.centreY(j);
            if (x > 0.4 && x < 0.8 && y > 0.3 && y < 0.5)
                CHECK(map.at(i, j) == Approx(design.targetDose).epsilon(0.015));
        }
    // Seed App. A: at the contour the exposure is about 5% of the plateau (the DFBTP edge
    // features fill the rest); 2% absolute covers the grid and the finite field.
    int iMid = grid.nx / 2;
    int jEdge = int((0.0 - grid.originY) / grid.pitch);  // cell whose lower edge is y = 0
    double atContour = 0.5 * (map.at(iMid, jEdge) + map.at(iMid, jEdge - 1));
    CHECK(atContour / design.targetDose == Approx(0.05).margin(0.02));
}
