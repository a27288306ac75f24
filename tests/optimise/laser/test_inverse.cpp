// The inverse planner's algorithm (optimise/laser/inverse.h) on its own: every figure compared is
// measured here from the returned plan (deposited and exposed through a fresh engine, the seed's
// exposure error of exposure_error.h against Etar written out from Eq. 14), not read from the
// planner's report. The comparison with the shipped `aces` planner, created through the registry,
// is tests/planners/test_inverse_vs_aces.cpp.
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

/// The default job's fitted kernel and process (see test_dfbtp.cpp); Ec 10 mJ/cm^2 delivered.
optimise::InverseParameters parameters(const kernel::FittedBeam& beam) {
    optimise::InverseParameters ip;
    auto& a = ip.base.aces;
    a.beamRadius = beam.radius;
    a.attenuationLength = beam.attenuationLength;
    a.depthOfMaximum = beam.depthOfMaximum;
    a.criticalDose = 0.1 / beam.efficiency;
    a.layerThickness = 0.05;
    a.laserPower = 10.0;
    a.edge = plan::AcesEdge::CureAtContour;
    return ip;  // wallOnContour false: the objective is the seed's exposure error itself
}

/// Etar = Ec exp((lt - zmax) / De3D) (seed 000 Eq. 14), Ec = 0.1 mJ/mm^2 in exposure-map units.
double etarOf(const kernel::FittedBeam& beam) {
    return 0.1 * std::exp((0.05 - beam.depthOfMaximum) / beam.attenuationLength);
}

/// Per-layer SSE (bottom first) of `plan` over `regions`, measured on a 10 um grid.
std::vector<double> layerSse(const plan::ScanPlan& plan,
                             const std::vector<geometry::PolygonSet>& regions,
                             const kernel::FittedBeam& beam) {
    exposure::ExposureEngine engine(optimise::planningGrid(regions, beam.radius, 0.01), beam, 0.05);
    const nlohmann::json e = optimise::planExposureError(engine, plan, regions, etarOf(beam),
                                                         plan::effectiveRadius(beam.radius));
    std::vector<double> sse;
    for (const auto& layer : e["layers"]) sse.push_back(layer["sse_mJ2_per_mm4"].get<double>());
    return sse;
}

plan::ScanPlan onePlan(const plan::LayerPlan& layer) {
    plan::ScanPlan p;
    p.machine.layerThickness = 0.05;
    p.layers = {layer};
    return p;
}

}  // namespace

// Issue 11: on the single-layer comparison the inverse plan is below DFBTP and below ACES with
// the cure-at-contour rule as the shipped `aces` planner designs a lone layer (the stack-aware
// rule with nothing above or below). Measured: ACES 66.8, DFBTP 104.4, inverse 56.9 mJ^2/mm^4
// (0.85 of ACES). 0.9 leaves 6% above the measurement (deterministic plans, float maps) and
// fails an inverse plan no better than ACES. The report's objective is half the SSE: checked
// against the measurement (1e-3: float maps), so that the figures the report prints are honest.
TEST_CASE("the inverse planner beats ACES and DFBTP on one layer", "[optimise][inverse]") {
    const kernel::FittedBeam beam{0.0632, 0.0367, 0.0022, 2.37};
    auto region = lShape();
    auto ip = parameters(beam);
    auto inverse = optimise::planInverse({region}, {0.05}, ip, beam);
    plan::AcesParameters contour = ip.base.aces;
    const plan::AcesStack alone;
    const double aces = layerSse(
        onePlan(plan::planAcesLayer(region, plan::designAces(contour, region, &alone), 10.0, 0.05)),
        {region}, beam)[0];
    auto dfbtp = optimise::planDfbtp({region}, {0.05}, ip.base, beam);
    const double dfbtpSse = layerSse(dfbtp.plan, {region}, beam)[0];
    const double inverseSse = layerSse(inverse.plan, {region}, beam)[0];
    INFO("SSE: ACES cure-at-contour " << aces << ", DFBTP " << dfbtpSse << ", inverse "
                                      << inverseSse << " (" << inverseSse / aces << " of ACES)");
    CHECK(inverseSse < 0.9 * aces);
    CHECK(inverseSse < 0.9 * dfbtpSse);
    CHECK(inverse.targetDose == Approx(etarOf(beam)).epsilon(1e-12));
    CHECK(2 * inverse.layers[0].finalObjective == Approx(inverseSse).epsilon(1e-3));
    for (const auto& pt : inverse.plan.layers[0].points) CHECK(pt.energy > 0);
}

// Never worse than its ACES warm start, whatever the budget (with no iterations the result is
// the start or ACES itself): on two layers of a square, each returned layer's measured SSE (its
// own map plus what the returned layer above transmits) against the same with that layer
// replaced by the ACES plan the planner designs for it. 1e-5 relative: float maps.
TEST_CASE("the inverse planner is never worse than ACES", "[optimise][inverse]") {
    const kernel::FittedBeam beam{0.05, 0.1, 0.0, 1.0};
    auto square = geometry::PolygonSet::rectangle({0, 0}, {0.6, 0.4});
    const std::vector<geometry::PolygonSet> regions{square, square};
    for (int iterations : {0, 3}) {
        auto ip = parameters(beam);
        ip.iterations = iterations;
        ip.dotPitch = 0.03;
        auto r = optimise::planInverse(regions, {0.05, 0.1}, ip, beam);
        const std::vector<double> planned = layerSse(r.plan, regions, beam);
        const plan::AcesDesign design = plan::designAces(ip.base.aces, square);
        for (size_t k = 0; k < regions.size(); ++k) {
            plan::ScanPlan withAces = r.plan;
            withAces.layers[k] = plan::planAcesLayer(square, design, 10.0, r.plan.layers[k].z);
            const double aces = layerSse(withAces, regions, beam)[k];
            INFO("iterations " << iterations << ", layer " << k << ": SSE " << planned[k]
                               << ", with ACES " << aces);
            CHECK(planned[k] <= aces * (1 + 1e-5));
        }
    }
}
