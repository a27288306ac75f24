#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/optimise/laser/inverse.h"
#include "vpsim/plan/feature_blocks.h"

using namespace vpsim;

namespace {

geometry::PolygonSet lShape() {
    return geometry::PolygonSet::rectangle({0, 0}, {2, 1})
        .unite(geometry::PolygonSet::rectangle({0, 1}, {1, 2}))
        .translated({-1, -1});
}

/// The default job's fitted kernel and process (see test_dfbtp.cpp).
optimise::InverseParameters parameters(const kernel::FittedBeam& beam) {
    optimise::InverseParameters ip;
    auto& a = ip.base.aces;
    a.beamRadius = beam.radius;
    a.attenuationLength = beam.attenuationLength;
    a.depthOfMaximum = beam.depthOfMaximum;
    a.criticalDose = 0.1 / beam.efficiency;
    a.layerThickness = 0.05;
    a.laserPower = 10.0;
    a.steadyPrintThrough = false;  // one layer: nothing above it
    a.edge = plan::AcesEdge::CureAtContour;
    return ip;
}

double sseOf(const plan::LayerPlan& layer, const geometry::PolygonSet& region,
             const kernel::FittedBeam& beam, double etar) {
    auto grid = optimise::planningGrid({region}, beam.radius, 0.01);
    exposure::ExposureEngine engine(grid, beam, 0.05);
    exposure::SurfaceGrid deposit = grid.surface();
    exposure::depositLayer(layer, deposit);
    return optimise::layerExposureError(engine.exposureMap(deposit), region, etar,
                                        plan::effectiveRadius(beam.radius))
        .sse;
}

}  // namespace

// Issue 11: on the single-layer comparison the inverse planner is below DFBTP and below ACES
// with the cure-at-contour rule; its objective is half the seed's SSE, so the reported
// objectives and the independently measured SSE must agree (1e-3: float maps).
TEST_CASE("the inverse planner beats ACES and DFBTP on one layer", "[optimise][inverse]") {
    const kernel::FittedBeam beam{0.0632, 0.0367, 0.0022, 2.37};
    auto region = lShape();
    auto ip = parameters(beam);
    auto inverse = optimise::planInverse({region}, {0.05}, ip, beam);
    const auto& rep = inverse.layers[0];
    const double etar = inverse.targetDose;
    plan::AcesParameters contour = ip.base.aces;
    contour.edge = plan::AcesEdge::CureAtContour;
    double aces = sseOf(plan::planAcesLayer(region, plan::designAces(contour, region), 10.0, 0.05),
                        region, beam, etar);
    auto dfbtp = optimise::planDfbtp({region}, {0.05}, ip.base, beam);
    double dfbtpSse = sseOf(dfbtp.plan.layers[0], region, beam, etar);
    double inverseSse = sseOf(inverse.plan.layers[0], region, beam, etar);
    INFO("SSE: ACES cure-at-contour " << aces << ", DFBTP " << dfbtpSse << ", inverse "
                                      << inverseSse << " (start " << 2 * rep.startObjective << ")");
    CHECK(2 * rep.acesObjective == Approx(aces).epsilon(1e-3));
    CHECK(2 * rep.finalObjective == Approx(inverseSse).epsilon(1e-3));
    CHECK(inverseSse < aces);
    CHECK(inverseSse < dfbtpSse);
    CHECK(rep.finalObjective <= rep.startObjective);
    CHECK_FALSE(rep.keptAces);
    for (const auto& pt : inverse.plan.layers[0].points) CHECK(pt.energy > 0);
}

// Never worse than its ACES start, whatever the budget: with no iterations the result is the
// start or ACES itself.
TEST_CASE("the inverse planner is never worse than ACES", "[optimise][inverse]") {
    const kernel::FittedBeam beam{0.05, 0.1, 0.0, 1.0};
    auto square = geometry::PolygonSet::rectangle({0, 0}, {0.6, 0.4});
    for (int iterations : {0, 3}) {
        auto ip = parameters(beam);
        ip.iterations = iterations;
        ip.dotPitch = 0.03;
        auto r = optimise::planInverse({square, square}, {0.05, 0.1}, ip, beam);
        for (const auto& rep : r.layers) {
            INFO("iterations " << iterations);
            CHECK(rep.finalObjective <= rep.acesObjective);
            bool startOrBetter = rep.finalObjective <= rep.startObjective * (1 + 1e-12);
            CHECK((startOrBetter || rep.keptAces));
        }
    }
}
