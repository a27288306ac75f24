/// Laser planners on one layer (seed 000 Fig. 22/23 and issue 11 item 9): the squared exposure
/// error of ACES (seed 5% edge rule and vpsim's cure-at-contour rule) and DFBTP on the default L
/// part at 10 um, and the planning time of a 10 x 10 mm layer at 10 um with its error ratio to
/// ACES. Prints one JSON object; the 1-minute load average tells how shared the 2 cores were.
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <iostream>

#include <nlohmann/json.hpp>

#include "vpsim/cure/threshold_law.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/geometry/slicer.h"
#include "vpsim/geometry/test_parts.h"
#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/optimise/laser/inverse.h"
#include "vpsim/plan/feature_blocks.h"
#include "vpsim/validate/slice_validator.h"

using namespace vpsim;

namespace {

const kernel::FittedBeam BEAM{0.0632, 0.0367, 0.0022,
                              2.37};  // examples/default.json's fitted kernel

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

/// Directory for the single-layer pictures (first command-line argument), empty for none.
std::string gPictures;

nlohmann::json compare(const geometry::PolygonSet& region, const std::string& name) {
    auto p = parameters();
    auto t0 = std::chrono::steady_clock::now();
    std::clock_t c1 = std::clock();
    auto dfbtp = optimise::planDfbtp({region}, {0.05}, p, BEAM);
    double dfbtpSeconds = seconds(t0), dfbtpCpu = double(std::clock() - c1) / CLOCKS_PER_SEC;
    plan::AcesParameters seed = p.aces, contour = p.aces;
    seed.borderCount = 0;
    contour.edge = plan::AcesEdge::CureAtContour;
    contour.steadyPrintThrough = false;
    t0 = std::chrono::steady_clock::now();
    auto aces5 = plan::planAcesLayer(region, plan::designAces(seed, region), 10.0, 0.05);
    double acesSeconds = seconds(t0);
    auto acesC = plan::planAcesLayer(region, plan::designAces(contour, region), 10.0, 0.05);
    optimise::InverseParameters ip;
    ip.base = p;
    ip.base.aces.steadyPrintThrough = false;
    ip.base.aces.edge = plan::AcesEdge::CureAtContour;
    t0 = std::chrono::steady_clock::now();
    std::clock_t c0 = std::clock();
    auto inverse = optimise::planInverse({region}, {0.05}, ip, BEAM);
    double inverseSeconds = seconds(t0), inverseCpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
    // The same without the coarse stage (the planning grid only), for the speed-up's price.
    optimise::InverseParameters fineOnly = ip;
    fineOnly.coarseIterations = 0;
    t0 = std::chrono::steady_clock::now();
    c0 = std::clock();
    auto inverseFine = optimise::planInverse({region}, {0.05}, fineOnly, BEAM);
    double fineSeconds = seconds(t0), fineCpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
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
    double si = sse(inverse.plan.layers[0]), sf = sse(inverseFine.plan.layers[0]);
    if (!gPictures.empty()) {
        std::vector<std::pair<std::string, optimise::ExposureError>> curves;
        for (auto [label, layer] : {std::pair{"ACES 5%", &aces5},
                                    {"ACES cure-at-contour", &acesC},
                                    {"DFBTP", &dfbtp.plan.layers[0]},
                                    {"inverse", &inverse.plan.layers[0]}}) {
            exposure::SurfaceGrid d = grid.surface();
            exposure::depositLayer(*layer, d);
            auto map = engine.exposureMap(d);
            curves.push_back(
                {label, optimise::layerExposureError(map, region, dfbtp.targetDose,
                                                     plan::effectiveRadius(BEAM.radius))});
            std::string file = std::string(label);
            for (char& ch : file)
                if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
            optimise::writeExposurePicture(gPictures + "/" + name + "_" + file + ".png", map,
                                           dfbtp.targetDose, 0.1);
        }
        optimise::writeErrorCurves(gPictures + "/" + name + "_error_curves.svg", curves);
    }
    return {{"sse_mJ2_per_mm4",
             {{"aces_5_percent", s5},
              {"aces_cure_at_contour", sc},
              {"dfbtp", sd},
              {"inverse", si},
              {"inverse_fine_grid_only", sf}}},
            {"dfbtp_over_aces_5_percent", sd / s5},
            {"dfbtp_over_aces_cure_at_contour", sd / sc},
            {"inverse_over_aces_5_percent", si / s5},
            {"inverse_over_aces_cure_at_contour", si / sc},
            {"inverse_iterations", inverse.layers[0].iterations},
            {"inverse_coarse_iterations", ip.coarseIterations},
            {"inverse_dots", inverse.layers[0].dots},
            {"plan_seconds",
             {{"aces", acesSeconds},
              {"dfbtp", dfbtpSeconds},
              {"inverse", inverseSeconds},
              {"inverse_fine_grid_only", fineSeconds}}},
            {"plan_cpu_seconds_all_threads",
             {{"dfbtp", dfbtpCpu}, {"inverse", inverseCpu}, {"inverse_fine_grid_only", fineCpu}}},
            {"grid_cells", double(grid.nx) * grid.ny},
            {"dfbtp_points", dfbtp.plan.layers[0].points.size()},
            {"dfbtp_vectors", dfbtp.plan.layers[0].vectors.size()}};
}

/// 3D with print-through that matters (kernel given: We3D 50 um, De3D 100 um = 2 layers): a 1 mm
/// column with a 0.6 mm ledge from z 0.5 to 1 mm (unsupported below). Each plan is exposed through
/// the engine and compared with the part (IoU, over-cure below down-facing surfaces).
nlohmann::json overhang() {
    const kernel::FittedBeam beam{0.05, 0.1, 0.0, 1.0};
    const double lt = 0.05, ec = 0.1;
    geometry::Mesh part = geometry::makeCellMesh({-0.5, 0.5, 1.1}, {-0.5, 0.5}, {0, 0.5, 0.75, 1.0},
                                                 {1, 0, 1, 1, 1, 1});
    auto layers = geometry::sliceMesh(part, geometry::SliceOptions{});
    std::vector<geometry::PolygonSet> regions;
    std::vector<double> tops;
    for (const auto& l : layers) regions.push_back(l.region), tops.push_back(l.zBottom + lt);
    optimise::DfbtpParameters p;
    p.aces.beamRadius = beam.radius;
    p.aces.attenuationLength = beam.attenuationLength;
    p.aces.criticalDose = ec;
    p.aces.layerThickness = lt;
    p.aces.laserPower = 10.0;
    auto grid = optimise::planningGrid(regions, beam.radius, 0.01);
    grid.slicesPerLayer = 5;
    exposure::ExposureEngine engine(grid, beam, lt);
    auto evaluate = [&](const plan::ScanPlan& plan) {
        const cure::ThresholdLaw law(ec);
        validate::SliceValidator validator(part, grid, law, lt / grid.slicesPerLayer);
        engine.run(plan, [&](const exposure::ExposureSlice& s) { validator.add(s); });
        auto v = validator.summary();
        return nlohmann::json{
            {"iou", v.iou},
            {"overcure_below_downfacing_median_um", v.overcureBelowDownFacingMedian * 1e3},
            {"overcure_below_downfacing_mean_um", v.overcureBelowDownFacingMean * 1e3},
            {"xy_contour_error_mean_um", v.xyContourErrorMean * 1e3}};
    };
    plan::ScanPlan aces;
    plan::AcesParameters contour = p.aces;
    contour.edge = plan::AcesEdge::CureAtContour;
    for (size_t k = 0; k < regions.size(); ++k)
        aces.layers.push_back(
            plan::planAcesLayer(regions[k], plan::designAces(contour, regions[k]), 10.0, tops[k]));
    auto t0 = std::chrono::steady_clock::now();
    auto dfbtp = optimise::planDfbtp(regions, tops, p, beam);
    double dfbtpSeconds = seconds(t0);
    optimise::InverseParameters ip;
    ip.base = p;
    ip.base.aces.edge = plan::AcesEdge::CureAtContour;
    t0 = std::chrono::steady_clock::now();
    auto inverse = optimise::planInverse(regions, tops, ip, beam);
    double inverseSeconds = seconds(t0);
    double uncompensable = 0;
    for (const auto& c : dfbtp.layers) uncompensable += c.uncompensableArea;
    return {{"part", "1 mm column, 0.6 mm ledge z 0.5..1 mm, 20 layers of 50 um"},
            {"kernel", "given: We3D 50 um, De3D 100 um, efficiency 1; Ec 10 mJ/cm^2"},
            {"aces_cure_at_contour", evaluate(aces)},
            {"dfbtp", evaluate(dfbtp.plan)},
            {"inverse", evaluate(inverse.plan)},
            {"dfbtp_uncompensable_area_mm2_sum_over_layers", uncompensable},
            {"plan_seconds", {{"dfbtp", dfbtpSeconds}, {"inverse", inverseSeconds}}}};
}

/// Issue 11's checks, each with the figures it compares (wall seconds on this machine's 2 cores).
nlohmann::json targets(const nlohmann::json& r) {
    const auto& l = r["l_part_2mm"];
    const auto& sq = r["square_10mm"]["plan_seconds"];
    const auto& o = r["overhang_3d"];
    const auto& lsse = l["sse_mJ2_per_mm4"];
    return {
        {"dfbtp_over_aces_5_percent_at_most_0.65", l["dfbtp_over_aces_5_percent"] <= 0.65},
        {"inverse_below_dfbtp_and_aces_cure_at_contour",
         lsse["inverse"] < lsse["dfbtp"] && lsse["inverse"] < lsse["aces_cure_at_contour"]},
        {"dfbtp_10mm_layer_under_1_s", sq["dfbtp"] < 1.0},
        {"inverse_10mm_layer_under_5_s", sq["inverse"] < 5.0},
        {"overhang_overcure_halved_iou_no_worse",
         o["dfbtp"]["overcure_below_downfacing_mean_um"].get<double>() <=
                 0.5 *
                     o["aces_cure_at_contour"]["overcure_below_downfacing_mean_um"].get<double>() &&
             o["dfbtp"]["iou"] >= o["aces_cure_at_contour"]["iou"] &&
             o["inverse"]["iou"] >= o["aces_cure_at_contour"]["iou"]}};
}

}  // namespace

int main(int argc, char** argv) {
    if (argc > 1) gPictures = argv[1];
    auto l = geometry::PolygonSet::rectangle({0, 0}, {2, 1})
                 .unite(geometry::PolygonSet::rectangle({0, 1}, {1, 2}))
                 .translated({-1, -1});
    auto square = geometry::PolygonSet::rectangle({-5, -5}, {5, 5});
    double load[1] = {0};
    getloadavg(load, 1);
    nlohmann::json out{{"benchmark", "laser_planners"},
                       {"grid_um", 10},
                       {"l_part_2mm", compare(l, "l_part")},
                       {"square_10mm", compare(square, "square_10mm")},
                       {"overhang_3d", overhang()},
                       {"load_average_1min", load[0]},
                       {"cores", 2}};
    out["targets"] = targets(out);
    std::cout << out.dump(2) << std::endl;
}
