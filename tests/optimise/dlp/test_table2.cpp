// Seed 001 Table 2 from the column optimiser: the Z dimensions of the holes and overhangs parts
// predicted on their pixel columns (exact cured profile of the optimised doses) against the
// means of the optimised prints S7-S12, and the geometric objective against the design.
// Column profiles from geometry/test_parts.h: holes part 11 mm high, holes z 2-5 and 7-8.5;
// overhangs part 10 mm, ledges z 7-10 (x = -3.5) and 3-4 (x = +3.5); 50 um layers.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "vpsim/optimise/dlp/cured_profile.h"
#include "vpsim/optimise/dlp/geometric.h"
#include "vpsim/optimise/dlp/pattern_search.h"

using namespace vpsim::optimise;

namespace {

const double DP = 0.365935872, K = 0.528080236, GEL = 0.276;  // Table 1 calibration

std::vector<uint8_t> column(int layers, std::vector<std::pair<double, double>> solidZ) {
    std::vector<uint8_t> s(size_t(layers), 0);
    for (auto [a, b] : solidZ)
        for (long k = std::lround(a / 0.05); k < std::lround(b / 0.05); ++k) s[size_t(k)] = 1;
    return s;
}

struct Feature {
    std::string name;
    std::vector<uint8_t> solid;
    bool gap;
    double zMin, zMax, objective;
    double measured = 0.0;  ///< mean of S7-S12 from the reference table
};

/// Means of the optimised samples (S7-S12) from tests/data/reference/seed001_table2_*.csv.
std::vector<Feature> features() {
    std::vector<uint8_t> holes = column(220, {{0, 2}, {5, 7}, {8.5, 11}});
    std::vector<Feature> f = {{"top hole", holes, true, 6.5, 9, 1.5},
                              {"bottom hole", holes, true, 1.5, 5.5, 3},
                              {"top overhang", column(200, {{7, 10}}), false, 0, 10, 3},
                              {"bottom overhang", column(200, {{3, 4}}), false, 0, 10, 1}};
    std::ifstream csv(std::string(VPSIM_SOURCE_DIR) +
                      "/tests/data/reference/seed001_table2_z_dimensions.csv");
    REQUIRE(csv);
    std::string line;
    double sums[4] = {0, 0, 0, 0};
    int counts[2] = {0, 0};
    while (std::getline(csv, line)) {
        if (line.empty() || line[0] == '#' || line.rfind("sample", 0) == 0) continue;
        std::stringstream s(line);
        std::string sample, kase, mode, top, topObj, bottom;
        std::getline(s, sample, ',');
        std::getline(s, kase, ',');
        std::getline(s, mode, ',');
        std::getline(s, top, ',');
        std::getline(s, topObj, ',');
        std::getline(s, bottom, ',');
        if (mode != "optimised") continue;
        int c = std::stoi(kase) - 1;
        sums[2 * c] += std::stod(top), sums[2 * c + 1] += std::stod(bottom), ++counts[c];
    }
    REQUIRE(counts[0] == 3);
    REQUIRE(counts[1] == 3);
    for (int i = 0; i < 4; ++i) f[size_t(i)].measured = sums[i] / 3.0;
    return f;
}

DlpColumnProblem paperProblem(Bonding bonding) {
    DlpColumnProblem p;
    p.layerThickness = 0.05;
    p.rateConstant = K;
    p.attenuation = 1.0 / DP;
    p.gelPoint = GEL;
    p.maxDose = 1.3;  // Opt 2: 130 mJ/cm^2
    p.targetConversion = 0.95;
    p.penalty = 5.5;
    p.bonding = bonding;
    return p;
}

double predicted(const Feature& f, const std::vector<double>& dose) {
    auto cured = curedIntervals(dose, 0.05, DP, -std::log1p(-GEL) / K);
    return f.gap ? uncuredLength(cured, f.zMin, f.zMax) : curedLength(cured, f.zMin, f.zMax);
}

}  // namespace

TEST_CASE("Table 2: own-layer optimum predicts every optimised feature within 0.2 mm",
          "[optimise][slow]") {
    // Issue 10's criterion: 0.2 mm of the S7-S12 means. Measured here: top hole 1.339 (1.350),
    // bottom hole 2.841 (2.943), top overhang 3.159 (2.980), bottom overhang 1.159 (1.077),
    // each proven optimal (gap 0). The run-bottom reading misses by up to 0.39 mm (next case),
    // which is why own-layer is the default.
    for (const Feature& f : features()) {
        DlpSearchResult r = solveColumnExactly(f.solid, paperProblem(Bonding::OwnLayer));
        double z = predicted(f, r.best.dose);
        INFO(f.name << ": predicted " << z << " mm, measured " << f.measured << " mm, gap "
                    << r.gap);
        REQUIRE(r.gap <= 1e-9);
        REQUIRE(std::abs(z - f.measured) <= 0.2);
    }
}

TEST_CASE("Table 2: run-bottom reading over-cures more than the prints show", "[optimise][slow]") {
    // Recorded, not a pass criterion of the paper: under run-bottom bonding the first exposure
    // of a run must cure down to the surface, so features overgrow by > 0.2 mm at d_max 130.
    double worst = 0.0;
    for (const Feature& f : features()) {
        DlpSearchResult r = solveColumnExactly(f.solid, paperProblem(Bonding::RunBottom));
        worst = std::max(worst, std::abs(predicted(f, r.best.dose) - f.measured));
    }
    REQUIRE(worst > 0.2);
}

TEST_CASE("Geometric objective: mean |Z - objective| <= 0.05 mm with own-layer bonding",
          "[optimise][slow]") {
    // Measured: +0.019, +0.019, -0.048, -0.050 mm (mean 0.034 mm), vs the paper's printed 0.08.
    double sum = 0.0;
    for (const Feature& f : features()) {
        DlpGeometricResult r = optimiseColumnGeometric(f.solid, paperProblem(Bonding::OwnLayer));
        double z = predicted(f, r.dose);
        INFO(f.name << ": " << z << " mm vs objective " << f.objective);
        REQUIRE(std::abs(z - f.objective) <= 0.05 + 1e-9);
        sum += std::abs(z - f.objective);
    }
    REQUIRE(sum / 4.0 <= 0.05);
}

TEST_CASE("Geometric objective: nothing cures outside the part in a synthetic column",
          "[optimise]") {
    // 20 void layers, 16 solid, 10 void, 12 solid: every void node stays below (1 - margin) Ec,
    // every solid node reaches Ec, and no cured interval reaches into the void by more than the
    // last solid layer's own thickness (the cure front lies inside that layer).
    std::vector<uint8_t> solid(58, 0);
    for (int k = 20; k < 36; ++k) solid[size_t(k)] = 1;
    for (int k = 46; k < 58; ++k) solid[size_t(k)] = 1;
    DlpColumnProblem p = paperProblem(Bonding::OwnLayer);
    DlpGeometricResult r = optimiseColumnGeometric(solid, p);
    const double ec = -std::log1p(-GEL) / K;
    REQUIRE(r.violation <= 1e-9);
    for (size_t k = 0; k < solid.size(); ++k) {
        if (solid[k])
            REQUIRE(r.accumulated[k] >= ec * (1 - 1e-9));
        else
            REQUIRE(r.accumulated[k] <= 0.95 * ec * (1 + 1e-9));
        REQUIRE(r.dose[k] <= p.maxDose * (1 + 1e-12));
        if (!solid[k]) REQUIRE(r.dose[k] == 0.0);
    }
    auto cured = curedIntervals(r.dose, 0.05, DP, ec);
    REQUIRE(cured.size() == 2);
    REQUIRE(cured[0].first >= 20 * 0.05);  // nothing below the designed surface
    REQUIRE(cured[0].second == Approx(36 * 0.05));
    REQUIRE(cured[1].first >= 46 * 0.05);
    REQUIRE(cured[1].first <= 47 * 0.05 + 1e-9);
}

TEST_CASE("Cured profile: one exposure cures its Jacobs depth", "[optimise]") {
    // A single dose d on the top layer of 40 cures Dp ln(d / Ec) below the top (Eq. 2),
    // crossing layer boundaries; tolerance 1e-12 mm.
    std::vector<double> d(40, 0.0);
    d[39] = 2.0;
    const double ec = -std::log1p(-GEL) / K;
    auto cured = curedIntervals(d, 0.05, DP, ec);
    REQUIRE(cured.size() == 1);
    REQUIRE(cured[0].second == Approx(2.0).margin(1e-12));
    REQUIRE(cured[0].first == Approx(2.0 - DP * std::log(2.0 / ec)).margin(1e-12));
    REQUIRE(uncuredLength(cured, 0.0, 2.0) == Approx(2.0 - DP * std::log(2.0 / ec)).margin(1e-12));
}
