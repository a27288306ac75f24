// The optimised-mask planner body: quantised masks whose doses are grey levels of the calibration,
// and the seed 001 hole column re-simulated after quantisation still within Table 2's 0.2 mm.
#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/optimise/dlp/cured_profile.h"
#include "vpsim/optimise/dlp/mask_optimiser.h"

using namespace vpsim;
using namespace vpsim::optimise;

namespace {

/// The grey curve of examples/*-optimised.json by hand: 12.2, 17 and 27 mW/cm^2 at grey 150,
/// 200 and 255, linear between, dark below 150, times the 5 s exposure (mJ/mm^2).
double handDose(int grey) {
    if (grey < 150) return 0.0;
    if (grey <= 200) return 5.0 * (0.122 + (grey - 150) * (0.17 - 0.122) / 50.0);
    return 5.0 * (0.17 + (grey - 200) * (0.27 - 0.17) / 55.0);
}

}  // namespace

TEST_CASE("busiest grey layer: the layer with the most distinct non-zero grey levels",
          "[optimise]") {
    // By hand: layer 0 dark, layer 1 one level (twice), layer 2 two levels, layer 3 two levels
    // and dark pixels (a tie with layer 2: the lower layer wins), layer 4 one level.
    const std::vector<std::vector<uint8_t>> grey{
        {0, 0, 0}, {160, 160, 0}, {160, 200, 200}, {0, 170, 255}, {255, 255, 255}};
    REQUIRE(busiestGreyLayer(grey) == 2);
    REQUIRE(busiestGreyLayer({{0, 0}, {0, 0}}) == 0);
}

TEST_CASE("optimised-mask: quantised hole column keeps Table 2 within 0.2 mm", "[optimise]") {
    // One pixel column of the holes part (220 layers). Grey curve of examples/*-optimised.json.
    DlpLayerStack part;
    part.width = part.height = 1;
    for (int k = 0; k < 220; ++k) {
        bool solid = k < 40 || (k >= 100 && k < 140) || k >= 170;
        part.layers.push_back({uint8_t(solid)});
    }
    DlpProcess process;
    process.rateConstant = 0.528080236;
    process.gelPoint = 0.276;
    process.penetrationDepth = 0.365935872;
    plan::GreyLevels levels({{150, 0.122}, {200, 0.17}, {255, 0.27}}, 5.0);
    DlpMaskPlan r = planOptimisedMasks(part, process, {}, levels);
    REQUIRE(r.plan.layers.size() == 220);
    std::vector<double> dose(220);
    long firstExposed = -1;
    for (int k = 0; k < 220; ++k) {
        const float d = r.plan.layers[k].masks[0].dose[0];
        const double wanted = r.optimised.dose[k][0];
        // The mask holds the dose of its grey level, by the calibration written out by hand.
        REQUIRE(d == float(handDose(r.grey[k][0])));
        // Quantised to the nearest grey level: no level of the 256 comes closer (brute force;
        // 1e-9 for ties between neighbours).
        for (int g = 0; g < 256; ++g)
            REQUIRE(std::abs(handDose(r.grey[k][0]) - wanted) <=
                    std::abs(handDose(g) - wanted) + 1e-9);
        if (d > 0 && firstExposed < 0) firstExposed = k;
        dose[k] = d;
    }
    auto cured = curedIntervals(dose, 0.05, process.penetrationDepth,
                                -std::log1p(-process.gelPoint) / process.rateConstant);
    const double top = uncuredLength(cured, 6.5, 9.0), bottom = uncuredLength(cured, 1.5, 5.5);
    INFO("after quantisation: top hole " << top << " mm, bottom hole " << bottom << " mm");
    REQUIRE(std::abs(top - (1.35 + 1.31 + 1.39) / 3) <= 0.2);
    REQUIRE(std::abs(bottom - (2.85 + 3.02 + 2.96) / 3) <= 0.2);
    REQUIRE(r.summary["distinct_columns"] == 1);
    // Figure data: the only column, the layer with the most grey levels, the uniform request.
    REQUIRE(r.figures["column"]["z_mm"].size() == 220);
    // One pixel per layer: every exposed layer shows one grey level, so the layer with the most
    // distinct grey levels is the lowest exposed one (ties go to the lowest index).
    REQUIRE(firstExposed >= 0);
    REQUIRE(r.figures["layer"].get<long>() == firstExposed);
    REQUIRE(r.summary["uniform_comparison"]["dose_mJ_per_cm2"].get<double>() > 0.0);
    // Fig. 13-14 data: conversion inside the solid runs near Phi_obj, below the gel point deep
    // in the holes (mid-hole nodes).
    nlohmann::json fig = dlpColumnFigureData(r, part, process, 0, 0);
    REQUIRE(fig["z_mm"].size() == 220);
    REQUIRE(fig["conversion"][70].get<double>() < 0.276);  // z 3.55 mm, inside the bottom hole
    REQUIRE(fig["conversion"][120].get<double>() > 0.9);   // z 6.05 mm, between the holes
    REQUIRE(fig["quantised_dose_mJ_per_cm2"][70].get<double>() == 0.0);
    DlpMaskPlannerSettings hot;
    hot.maxDose = 2.6;  // above grey 255's 1.35 mJ/mm^2
    REQUIRE_THROWS_WITH(planOptimisedMasks(part, process, hot, levels),
                        Catch::Contains("brightest grey"));
}
