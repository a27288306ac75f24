/// Laser planners on one layer (seed 000 Fig. 22/23 and issue 11 item 9): the squared exposure
/// error of ACES (seed 5% edge rule and vpsim's cure-at-contour rule) and DFBTP on the default L
/// part at 10 um, and the planning time of a 10 x 10 mm layer at 10 um with its error ratio to
/// ACES. Prints one JSON object; the 1-minute load average tells how shared the 2 cores were.
#include <chrono>
#include <cstdlib>
#include <iostream>

#include <nlohmann/json.hpp>

#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/dfbtp_exposure_error.h"
#include "vpsim/optimise/dfbtp_planner.h"
#include "vpsim/plan/feature_blocks.h"

using namespace vpsim;

namespace {

const kernel::FittedBeam BEAM{0.0632, 0.0367, 0.0022, 2.37};  // examples/default.json's fitted kernel

optimise::DfbtpParameters parameters() {
    optimise::DfbtpParameters p;
    p.aces.beamRadius = BEAM.radius;
    p.aces.attenuationLength = BEAM.attenuationLength;
    p.aces.depthOfMaximum = 0.0022;
    p.aces.criticalDose = 0.1 / BEAM.efficiency;
    p.aces.layerThickness = 0.05;
    p.aces.laserPower = 10.0;
    return p;
}

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

nlohmann::json compare(const geometry::PolygonSet& region) {
    auto p = parameters();
    auto t0 = std::chrono::steady_clock::now();
    auto dfbtp = optimise::planDfbtp({region}, {0.05}, p, BEAM);
    double dfbtpSeconds = seconds(t0);
    plan::AcesParameters seed = p.aces, contour = p.aces;
    seed.borderCount = 0;
    contour.edge = plan::AcesEdge::CureAtContour;
    contour.steadyPrintThrough = false;
    t0 = std::chrono::steady_clock::now();
    auto aces5 = plan::planAcesLayer(region, plan::designAces(seed, region), 10.0, 0.05);
    double acesSeconds = seconds(t0);
    auto acesC = plan::planAcesLayer(region, plan::designAces(contour, region), 10.0, 0.05);
    auto grid = optimise::planningGrid({region}, BEAM.radius, 0.01);
    exposure::ExposureEngine engine(grid, BEAM, 0.05);
    auto sse = [&](const plan::LayerPlan& l) {
        exposure::SurfaceGrid d(grid.nx, grid.ny, grid.originX, grid.originY, grid.pitch);
        exposure::depositLayer(l, d);
        return optimise::layerExposureError(engine.exposureMap(d), region, dfbtp.targetDose,
                                            plan::effectiveRadius(BEAM.radius))
            .sse;
    };
    double s5 = sse(aces5), sc = sse(acesC), sd = sse(dfbtp.plan.layers[0]);
    return {{"sse_mJ2_per_mm4", {{"aces_5_percent", s5}, {"aces_cure_at_contour", sc}, {"dfbtp", sd}}},
            {"dfbtp_over_aces_5_percent", sd / s5},
            {"dfbtp_over_aces_cure_at_contour", sd / sc},
            {"plan_seconds", {{"aces", acesSeconds}, {"dfbtp", dfbtpSeconds}}},
            {"grid_cells", double(grid.nx) * grid.ny},
            {"dfbtp_points", dfbtp.plan.layers[0].points.size()},
            {"dfbtp_vectors", dfbtp.plan.layers[0].vectors.size()}};
}

}  // namespace

int main() {
    auto l = geometry::PolygonSet::rectangle({0, 0}, {2, 1})
                 .unite(geometry::PolygonSet::rectangle({0, 1}, {1, 2}))
                 .translated({-1, -1});
    auto square = geometry::PolygonSet::rectangle({-5, -5}, {5, 5});
    double load[1] = {0};
    getloadavg(load, 1);
    nlohmann::json out{{"benchmark", "laser_planners"},
                       {"grid_um", 10},
                       {"l_part_2mm", compare(l)},
                       {"square_10mm", compare(square)},
                       {"inverse", "not implemented yet"},
                       {"load_average_1min", load[0]},
                       {"cores", 2}};
    std::cout << out.dump(2) << std::endl;
}
