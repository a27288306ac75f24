#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/plan/feature_blocks.h"

using namespace vpsim;

namespace {

/// The default job's L part (examples/default.json: test part l-shape, size 2 mm, centred).
geometry::PolygonSet lShape(double s = 2.0) {
    auto a = geometry::PolygonSet::rectangle({0, 0}, {s, s / 2});
    auto b = geometry::PolygonSet::rectangle({0, s / 2}, {s / 2, s});
    return a.unite(b).translated({-s / 2, -s / 2});
}

/// The default job's fitted Monte Carlo kernel (report.json of examples/default.json): We3D
/// 63.2 um, De3D 36.7 um, zmax 2.2 um, efficiency 2.37; Ec 10 mJ/cm^2, 10 mW, 50 um layers.
struct Setup {
    kernel::FittedBeam beam{0.0632, 0.0367, 0.0022, 2.37};
    optimise::DfbtpParameters p;
    Setup() {
        p.aces.beamRadius = beam.radius;
        p.aces.attenuationLength = beam.attenuationLength;
        p.aces.depthOfMaximum = 0.0022;
        p.aces.criticalDose = 0.1 / beam.efficiency;
        p.aces.layerThickness = 0.05;
        p.aces.laserPower = 10.0;
    }
};

/// Own exposure map of a layer plan on `grid`.
exposure::SurfaceGrid mapOf(const plan::LayerPlan& layer, const exposure::ExposureGrid& grid,
                            const kernel::FittedBeam& beam) {
    exposure::ExposureEngine engine(grid, beam, 0.05);
    exposure::SurfaceGrid deposit(grid.nx, grid.ny, grid.originX, grid.originY, grid.pitch);
    exposure::depositLayer(layer, deposit);
    return engine.exposureMap(deposit);
}

double energyOf(const plan::LayerPlan& layer) {
    double e = 0;
    for (const auto& pt : layer.points) e += pt.energy;
    for (const auto& v : layer.vectors)
        e += v.power / v.speed * std::hypot(v.x1 - v.x0, v.y1 - v.y0);
    return e;
}

}  // namespace

// Seed 000 Fig. 22/23: on one layer (nothing above it) DFBTP's squared exposure error is 39
// against ACES's 60 mJ^2/mm^4 (ratio 0.65) with the seed's 5% edge rule. Here: the default L part
// on a 10 um grid, errors over the part plus Reff. Measured: DFBTP 104.4, ACES 5% 295.9 (ratio
// 0.35, the seed's 0.65 holds with room), ACES with vpsim's cure-at-contour rule 66.8 (as the
// shipped `aces` planner designs it for a single layer: the stack-aware rule with nothing above
// or below). So DFBTP does NOT beat ACES cure-at-contour on this metric: it is 1.76x its error
// with its 40 um dot pitch (1.56x at 20 um, which cost 4.9x ACES's build time, issue 23).
// DFBTP, held below the cure level outside by its liftings, lets less of its tail out but
// undershoots Etar inside, where ACES cure-at-contour cures out to the contour at the surface;
// the inverse planner goes below both (test_inverse_vs_aces.cpp in tests/planners).
TEST_CASE("DFBTP lowers the single-layer exposure error of ACES as in seed 000",
          "[optimise][dfbtp]") {
    Setup s;
    auto region = lShape();
    optimise::DfbtpResult dfbtp = optimise::planDfbtp({region}, {0.05}, s.p, s.beam);
    REQUIRE(dfbtp.plan.layers.size() == 1);
    const auto grid = optimise::planningGrid({region}, s.beam.radius, 0.01);
    const double etar = dfbtp.targetDose, reff = plan::effectiveRadius(s.beam.radius);

    plan::AcesParameters seed = s.p.aces;
    seed.borderCount = 0;
    plan::LayerPlan aces5 = plan::planAcesLayer(region, plan::designAces(seed, region), 10.0, 0.05);
    plan::AcesParameters contour = s.p.aces;
    contour.edge = plan::AcesEdge::CureAtContour;
    const plan::AcesStack alone;  // one layer: nothing above, nothing below
    plan::LayerPlan acesC =
        plan::planAcesLayer(region, plan::designAces(contour, region, &alone), 10.0, 0.05);

    auto errorOf = [&](const plan::LayerPlan& l) {
        return optimise::layerExposureError(mapOf(l, grid, s.beam), region, etar, reff);
    };
    auto eAces5 = errorOf(aces5), eAcesC = errorOf(acesC), eDfbtp = errorOf(dfbtp.plan.layers[0]);
    INFO("SSE mJ^2/mm^4: ACES 5% " << eAces5.sse << ", ACES cure-at-contour " << eAcesC.sse
                                   << ", DFBTP " << eDfbtp.sse << " (DFBTP / ACES 5% "
                                   << eDfbtp.sse / eAces5.sse << ", / ACES cure-at-contour "
                                   << eDfbtp.sse / eAcesC.sse << ")");
    // The seed's figure: at most 0.65 of ACES with its 5% rule (measured 0.40; 0.35 at 20 um).
    CHECK(eDfbtp.sse <= 0.65 * eAces5.sse);
    // The claim as measured: ACES cure-at-contour stays below DFBTP, and DFBTP within 1.7x of it
    // (measured 1.76x at the 40 um dot pitch, 1.78x with the corners on the edge rows' lines; the
    // plans are deterministic, the 8% leaves room for float sums on other platforms and small
    // design changes, not for a DFBTP that falls further behind). If DFBTP ever beats it, the first
    // check fails so that this statement gets corrected.
    CHECK(eAcesC.sse < eDfbtp.sse);
    CHECK(eDfbtp.sse < 1.9 * eAcesC.sse);
    CHECK(dfbtp.layers[0].edgeBlocks == 6);
    CHECK(dfbtp.layers[0].cornerBlocks == 6);
    for (const auto& pt : dfbtp.plan.layers[0].points) CHECK(pt.energy > 0);
    for (const auto& v : dfbtp.plan.layers[0].vectors) CHECK(v.speed > 0);
}

// Eq. 21-22 on two layers: the lower layer aims at its target minus what the upper one sends
// down, exp(-lt/De) times the upper layer's own map (the direct sum of Eq. 21 for n = 2).
// Tapered (narrow on top): compensation removes most of the lower layer's error. Bottom-narrow:
// the excess outside the lower region cannot be taken back and is reported.
TEST_CASE("DFBTP compensates the exposure transmitted from the layer above", "[optimise][dfbtp]") {
    Setup s;
    s.beam.attenuationLength = 0.1;  // print-through that matters: De = 2 lt
    s.p.aces.attenuationLength = 0.1;
    auto big = geometry::PolygonSet::rectangle({-0.6, -0.6}, {0.6, 0.6});
    auto small = geometry::PolygonSet::rectangle({-0.4, -0.4}, {0.4, 0.4});
    const auto grid = optimise::planningGrid({small, big}, s.beam.radius, 0.01);
    const double decay = std::exp(-0.05 / 0.1), reff = plan::effectiveRadius(s.beam.radius);
    auto lowerError = [&](const optimise::DfbtpResult& r, const geometry::PolygonSet& lower) {
        auto total = mapOf(r.plan.layers[0], grid, s.beam);
        auto upper = mapOf(r.plan.layers[1], grid, s.beam);
        for (size_t c = 0; c < upper.values.size(); ++c)
            total.values[c] += float(decay * upper.values[c]);  // Eq. 21, n = 2
        return optimise::layerExposureError(total, lower, r.targetDose, reff);
    };
    auto tapered = optimise::planDfbtp({big, small}, {0.05, 0.1}, s.p, s.beam);
    auto narrow = optimise::planDfbtp({small, big}, {0.05, 0.1}, s.p, s.beam);
    s.p.compensate = false;
    auto taperedU = optimise::planDfbtp({big, small}, {0.05, 0.1}, s.p, s.beam);
    // The top layer does not depend on compensation.
    CHECK(energyOf(tapered.plan.layers[1]) ==
          Approx(energyOf(taperedU.plan.layers[1])).epsilon(1e-9));
    auto eC = lowerError(tapered, big), eU = lowerError(taperedU, big);
    INFO("tapered lower layer SSE with compensation " << eC.sse << ", without " << eU.sse);
    CHECK(eC.sse < 0.5 * eU.sse);
    CHECK(energyOf(tapered.plan.layers[0]) < energyOf(taperedU.plan.layers[0]));
    CHECK(tapered.layers[0].uncompensableArea < 0.05);
    // Bottom-narrow: outside the small layer the big one sends about decay * Etar.
    CHECK(narrow.layers[0].uncompensableArea > 0.5 * (big.area() - small.area()));
    CHECK(narrow.layers[0].uncompensableMax == Approx(decay).margin(0.15));
    CHECK(narrow.layers[1].uncompensableArea == 0);
    for (const auto& r : {tapered, narrow})
        for (const auto& l : r.plan.layers)
            for (const auto& pt : l.points) CHECK(pt.energy >= 0);
}

// The plan-wide metric on two identical layers: the top layer's error is its own map's, the
// lower layer's is on its map plus exp(-lt/De) times the upper map (the direct sum of Eq. 21).
TEST_CASE("the plan exposure error adds what the layers above transmit", "[optimise][dfbtp]") {
    Setup s;
    auto square = geometry::PolygonSet::rectangle({-0.4, -0.4}, {0.4, 0.4});
    auto r = optimise::planDfbtp({square, square}, {0.05, 0.1}, s.p, s.beam);
    auto grid = optimise::planningGrid({square}, s.beam.radius, 0.01);
    exposure::ExposureEngine engine(grid, s.beam, 0.05);
    const double reff = plan::effectiveRadius(s.beam.radius), etar = r.targetDose;
    auto json = optimise::planExposureError(engine, r.plan, {square, square}, etar, reff);
    auto upper = mapOf(r.plan.layers[1], grid, s.beam),
         lower = mapOf(r.plan.layers[0], grid, s.beam);
    const double decay = std::exp(-0.05 / s.beam.attenuationLength);
    for (size_t c = 0; c < lower.values.size(); ++c)
        lower.values[c] += float(decay * upper.values[c]);
    double sseTop = optimise::layerExposureError(upper, square, etar, reff).sse;
    double sseLow = optimise::layerExposureError(lower, square, etar, reff).sse;
    CHECK(json["top_layer"]["sse_mJ2_per_mm4"].get<double>() == Approx(sseTop).epsilon(1e-4));
    CHECK(json["layers"][0]["sse_mJ2_per_mm4"].get<double>() == Approx(sseLow).epsilon(1e-3));
    CHECK(json["sse_mJ2_per_mm4"].get<double>() == Approx(sseTop + sseLow).epsilon(1e-3));
}

// Small features (issue 23): a corner between two edge blocks is planned on the lines of the
// edges' rows, continued through the corner block, so that each row and its corner pieces are
// one straight scan line at one speed (power modulated along it) instead of a row plus a grid of
// corner dots, each dot row a scan line of its own. The rows run around the contour, offset after
// offset (ACES's border loops), so the scanner turns by the contour's angle between them.
TEST_CASE("DFBTP runs an edge row on through its corners", "[optimise][dfbtp]") {
    Setup s;
    const auto region = geometry::PolygonSet::rectangle({0, 0}, {1.0, 0.6});
    optimise::DfbtpResult r = optimise::planDfbtp({region}, {0.05}, s.p, s.beam);
    const plan::LayerPlan& layer = r.plan.layers[0];
    CHECK(r.layers[0].cornerBlocks == 4);
    CHECK(r.layers[0].cornerDots > 0);
    CHECK(layer.points.empty());  // every corner dot is a piece of a row line
    const plan::AcesDesign design = plan::designAces(s.p.aces, region);
    const double reff = plan::effectiveRadius(s.beam.radius);
    const plan::FeatureBlocks blocks =
        plan::disassembleFeatures(region, design.edgeOffset, reff, s.beam.radius);
    // Scan lines: runs of chained collinear vectors in plan order.
    int lines = 0, fromCorners = 0;
    for (size_t k = 0; k < layer.vectors.size(); ++k) {
        const plan::LaserVector &v = layer.vectors[k], *u = k ? &layer.vectors[k - 1] : nullptr;
        const double ax = v.x1 - v.x0, ay = v.y1 - v.y0;
        const bool goesOn = u && std::abs(u->x1 - v.x0) < 1e-9 && std::abs(u->y1 - v.y0) < 1e-9 &&
                            std::abs((u->x1 - u->x0) * ay - (u->y1 - u->y0) * ax) < 1e-12;
        if (goesOn) continue;
        ++lines;
        for (const auto& corner : blocks.corners)  // a row continued back through a corner
            fromCorners += std::abs(v.x0 - corner.vertex.x) < corner.halfSize &&
                           std::abs(v.y0 - corner.vertex.y) < corner.halfSize;
    }
    // At most one line per row offset on each of the four edges, plus the middle's hatch lines
    // (ACES's middle area, cut into pieces along them): the corners add no lines of their own.
    const int rowsPerEdge = int(std::floor((reff + design.edgeOffset) / s.p.dotPitch + 1e-9)) + 1;
    const int hatchLines =
        int(plan::planAcesLayer(blocks.middle, design, 10.0, 0.05).vectors.size());
    INFO("scan lines " << lines << " (" << fromCorners
                       << " start in a corner block), rows per edge " << rowsPerEdge
                       << ", hatch lines " << hatchLines);
    CHECK(fromCorners > 0);
    CHECK(lines <= 4 * rowsPerEdge + hatchLines);
    for (const auto& v : layer.vectors) CHECK(v.speed > 0);
}
