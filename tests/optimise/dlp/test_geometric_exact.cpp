// The geometric objective's optimum certified on small columns: enumeration of every exposure
// pattern (an LP each) equals GLPK's branch and cut on the MILP, the LP's objective equals the
// objective computed directly from the doses, the doses keep Eq. 10 as exposureBounds states it
// (separate code from the LP's rows), and no point of a brute-force dose grid does better.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>

#include "dlp_test_support.h"
#include "vpsim/optimise/dlp/geometric.h"

using namespace vpsim::optimise;

namespace {

DlpColumnProblem seedResin(Bonding bonding) {
    return vpsim::test::seedResin(1.3, bonding);
}

/// Small columns with void gaps (down-facing surfaces) and runs of several layers.
const std::vector<std::vector<uint8_t>> COLUMNS = {{1, 1, 1},
                                                   {0, 1, 1, 1},
                                                   {1, 0, 1, 1},
                                                   {1, 1, 0, 0, 1, 1},
                                                   {0, 0, 1, 1, 1, 1, 1, 0},
                                                   {1, 1, 1, 0, 1, 1, 1, 1, 1}};

bool printable(const std::vector<uint8_t>& solid, const DlpColumnProblem& p,
               const std::vector<double>& dose) {
    std::vector<uint8_t> exposed(solid.size());
    for (size_t k = 0; k < solid.size(); ++k) exposed[k] = dose[k] > 0.0;
    std::vector<double> lo, hi;
    try {
        if (!exposureBounds(exposed, solid, p, lo, hi)) return false;
    } catch (...) {
        return false;  // a dose on a void layer
    }
    for (size_t k = 0; k < solid.size(); ++k)
        if (dose[k] < lo[k] * (1 - 1e-9) || dose[k] > hi[k] * (1 + 1e-9)) return false;
    return true;
}

}  // namespace

TEST_CASE("geometric: enumeration equals branch and cut and keeps Eq. 10", "[optimise]") {
    // Both exact; tolerance 1e-9 relative (simplex round-off on objectives of order 1-100).
    for (Bonding bonding : {Bonding::OwnLayer, Bonding::RunBottom})
        for (const auto& solid : COLUMNS) {
            const DlpColumnProblem p = seedResin(bonding);
            DlpGeometricResult e = enumerateColumnGeometric(solid, p);
            DlpGeometricResult b = branchAndCutColumnGeometric(solid, p);
            INFO("layers " << solid.size() << " enumeration " << e.objective << " branch and cut "
                           << b.objective);
            REQUIRE(e.optimal);
            REQUIRE(e.gap == 0.0);
            REQUIRE(e.objective == Approx(b.objective).epsilon(1e-9).margin(1e-12));
            REQUIRE(geometricObjective(solid, p, {}, e.dose) ==
                    Approx(e.objective).epsilon(1e-7).margin(1e-9));
            REQUIRE(printable(solid, p, e.dose));
            // optimiseColumnGeometric enumerates these (<= 10 solid layers): the same optimum.
            REQUIRE(optimiseColumnGeometric(solid, p).objective ==
                    Approx(e.objective).epsilon(1e-9).margin(1e-12));
        }
}

TEST_CASE("geometric: no dose on a brute-force grid beats the certified optimum", "[optimise]") {
    // Every pattern of 3-4 layer columns, each exposed dose on 41 points of its Eq. 10 box
    // [lo, hi] (exposureBounds): the grid's best is never below the optimum (1e-9), and comes
    // within 2 % of it (the optimum is a vertex the grid only approximates).
    for (const auto& solid : {std::vector<uint8_t>{1, 1, 1}, std::vector<uint8_t>{0, 1, 1, 1},
                              std::vector<uint8_t>{1, 0, 1, 1}}) {
        const DlpColumnProblem p = seedResin(Bonding::OwnLayer);
        const double optimum = enumerateColumnGeometric(solid, p).objective;
        const size_t n = solid.size();
        double gridBest = INFINITY;
        for (uint32_t mask = 0; mask < (1u << n); ++mask) {
            std::vector<uint8_t> exposed(n);
            bool ok = true;
            for (size_t k = 0; k < n; ++k) {
                exposed[k] = (mask >> k) & 1;
                ok = ok && (!exposed[k] || solid[k]);
            }
            std::vector<double> lo, hi;
            if (!ok || !exposureBounds(exposed, solid, p, lo, hi)) continue;
            std::vector<double> dose(n, 0.0);
            std::function<void(size_t)> walk = [&](size_t k) {
                if (k == n) {
                    gridBest = std::min(gridBest, geometricObjective(solid, p, {}, dose));
                    return;
                }
                if (!exposed[k]) return walk(k + 1);
                for (int i = 0; i <= 40; ++i) {
                    dose[k] = lo[k] + (hi[k] - lo[k]) * i / 40.0;
                    walk(k + 1);
                }
                dose[k] = 0.0;
            };
            walk(0);
        }
        INFO("optimum " << optimum << " grid " << gridBest);
        REQUIRE(gridBest >= optimum - 1e-9);
        REQUIRE(gridBest <= optimum * 1.02 + 1e-6);
    }
}

TEST_CASE("geometric: the local search against the certified optimum", "[optimise]") {
    // The search used beyond enumerationLimit, forced on small columns: never below the exact
    // optimum, and its stated lower bound never above it.
    for (const auto& solid : COLUMNS) {
        const DlpColumnProblem p = seedResin(Bonding::OwnLayer);
        const DlpGeometricResult exact = enumerateColumnGeometric(solid, p);
        DlpGeometricOptions search;
        search.enumerationLimit = 0;
        const DlpGeometricResult local = optimiseColumnGeometric(solid, p, search);
        INFO("exact " << exact.objective << " local " << local.objective << " bound "
                      << local.lowerBound);
        REQUIRE(local.objective >= exact.objective * (1 - 1e-9) - 1e-12);
        REQUIRE(local.lowerBound <= exact.objective * (1 + 1e-9) + 1e-12);
    }
}
