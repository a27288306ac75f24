// The fast geometric pattern solvers against the reference: the chain LP (one variable per
// exposure, lazily added gel rows) equals GLPK on the full per-layer LP, the band trajectory
// (no LP) is within its stated light-term tolerance of the chain LP and never below it, the
// structural lower bound never exceeds the certified optimum (enumeration), and the greedy start
// patterns keep Eq. 10 as exposureBounds states it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "dlp_test_support.h"
#include "vpsim/optimise/dlp/geometric_chain.h"
#include "vpsim/optimise/dlp/geometric_lp.h"

using namespace vpsim::optimise;

namespace {

DlpColumnProblem seedResin(Bonding bonding) {
    return vpsim::test::seedResin(1.3, bonding);
}

/// A column of `n` layers: solid runs of 1-25 layers between voids of 1-8 (or the platform).
std::vector<uint8_t> randomColumn(std::mt19937& rng, size_t n) {
    std::uniform_int_distribution<int> run(1, 25), gap(1, 8), coin(0, 1);
    std::vector<uint8_t> solid(n, 0);
    size_t k = coin(rng) ? 0 : size_t(gap(rng));
    while (k < n) {
        for (int i = run(rng); i > 0 && k < n; --i) solid[k++] = 1;
        k += size_t(gap(rng));
    }
    return solid;
}

/// A random pattern: each solid layer exposed with probability `density`.
std::vector<uint8_t> randomPattern(std::mt19937& rng, const std::vector<uint8_t>& solid,
                                   double density) {
    std::bernoulli_distribution on(density);
    std::vector<uint8_t> pattern(solid.size(), 0);
    for (size_t k = 0; k < solid.size(); ++k) pattern[k] = solid[k] && on(rng);
    return pattern;
}

double lightPerEc(const DlpColumnProblem& p, const std::vector<double>& dose) {
    double sum = 0.0;
    for (double d : dose) sum += d;
    return sum * std::exp(-p.attenuation * p.layerThickness) /
           bondingDose(p.rateConstant, p.attenuation, p.gelPoint, p.layerThickness, 1);  // / Ec
}

}  // namespace

TEST_CASE("geometric chain LP equals the full per-layer LP", "[optimise]") {
    std::mt19937 rng(7);
    int compared = 0;
    for (Bonding bonding : {Bonding::OwnLayer, Bonding::RunBottom})
        for (int trial = 0; trial < 30; ++trial) {
            const DlpColumnProblem p = seedResin(bonding);
            const std::vector<uint8_t> solid = randomColumn(rng, 30 + size_t(trial) * 3);
            GeometricPatternLp full(solid, p, {});
            GeometricChainLp chain(solid, p, {});
            for (int q = 0; q < 4; ++q) {
                const std::vector<uint8_t> pattern =
                    q == 0 ? greedyPattern(solid, p, longestGap(p))
                           : randomPattern(rng, solid, 0.15 + 0.2 * q);
                std::vector<double> a, b;
                const double reference = full.solve(pattern, a), value = chain.solveLp(pattern, b);
                INFO("trial " << trial << " pattern " << q);
                REQUIRE(std::isinf(reference) == std::isinf(value));
                if (std::isinf(value)) continue;
                REQUIRE(value == Approx(reference).epsilon(1e-9).margin(1e-9));
                REQUIRE(geometricObjective(solid, p, {}, b) ==
                        Approx(value).epsilon(1e-7).margin(1e-9));
                ++compared;
            }
        }
    REQUIRE(compared > 150);
}

TEST_CASE("geometric band trajectory is within the light term of the LP", "[optimise]") {
    // Without an LP only when every gel condition can be met; then its objective is the LP's up
    // to the 1e-4-per-Ec light term it does not trade (never below the LP's optimum).
    std::mt19937 rng(11);
    size_t banded = 0, patterns = 0;
    for (Bonding bonding : {Bonding::OwnLayer, Bonding::RunBottom})
        for (int trial = 0; trial < 40; ++trial) {
            const DlpColumnProblem p = seedResin(bonding);
            const std::vector<uint8_t> solid = randomColumn(rng, 25 + size_t(trial) * 4);
            GeometricChainLp fast(solid, p, {});
            GeometricChainLp exact(solid, p, {});
            for (int gap = 1; gap <= longestGap(p); ++gap)
                for (const auto& pattern :
                     {greedyPattern(solid, p, gap), periodicPattern(solid, gap, 0),
                      periodicPattern(solid, gap, bottomSkip(p, gap))}) {
                    std::vector<double> a, b;
                    const double value = fast.solve(pattern, a),
                                 reference = exact.solveLp(pattern, b);
                    REQUIRE(std::isinf(reference) == std::isinf(value));
                    if (std::isinf(value)) continue;
                    ++patterns;
                    INFO("trial " << trial << " gap " << gap << " value " << value << " LP "
                                  << reference);
                    REQUIRE(value >= reference - 1e-9 * std::max(1.0, reference));
                    REQUIRE(value <= reference + 1e-4 * lightPerEc(p, a) + 1e-9);
                    REQUIRE(geometricObjective(solid, p, {}, a) ==
                            Approx(value).epsilon(1e-7).margin(1e-9));
                }
            banded += fast.solves() - fast.lpSolves();
        }
    INFO("banded " << banded << " of " << patterns);
    REQUIRE(banded > 50);  // the shortcut is exercised (about 1 pattern in 10 here)
}

TEST_CASE("geometric structural bound never exceeds the optimum", "[optimise]") {
    std::mt19937 rng(3);
    for (Bonding bonding : {Bonding::OwnLayer, Bonding::RunBottom})
        for (int trial = 0; trial < 25; ++trial) {
            const DlpColumnProblem p = seedResin(bonding);
            std::vector<uint8_t> solid = randomColumn(rng, 14);
            size_t count = size_t(std::count(solid.begin(), solid.end(), 1));
            for (size_t k = solid.size(); count > 10 && k-- > 0;)  // enumerable: <= 10 solid
                if (solid[k]) solid[k] = 0, --count;
            if (count == 0) continue;
            const DlpGeometricResult exact = enumerateColumnGeometric(solid, p);
            const double bound = structuralBound(solid, p, {});
            INFO("trial " << trial << " optimum " << exact.objective << " bound " << bound);
            REQUIRE(bound <= exact.objective * (1 + 1e-9) + 1e-12);
            REQUIRE(optimiseColumnGeometric(solid, p).lowerBound <=
                    exact.objective * (1 + 1e-9) + 1e-12);
        }
    // Larger columns, beyond enumeration: the reported bound must lie below the optimum of every
    // pattern we can solve independently (GLPK on the full per-layer LP of the greedy start
    // patterns and of random ones; the optimum is the least of all patterns'), and the search's
    // own result is re-evaluated from its doses. The search starts from the greedy patterns of
    // the longest `startGaps` gaps, so it must end no worse than the best of those (up to the
    // band trajectory's light-term tolerance, 1e-4 per Ec of light, see above). (Greedy patterns
    // of shorter gaps are not among its starts, and one of them does beat its result here:
    // in one of these columns 50.98 against 52.82; the search is a heuristic, certified by its
    // bound only.)
    int solvedPatterns = 0;
    for (Bonding bonding : {Bonding::OwnLayer, Bonding::RunBottom})
        for (int trial = 0; trial < 15; ++trial) {
            const DlpColumnProblem p = seedResin(bonding);
            const std::vector<uint8_t> solid = randomColumn(rng, 60 + size_t(trial) * 8);
            if (std::count(solid.begin(), solid.end(), 1) == 0) continue;
            const DlpGeometricResult r = optimiseColumnGeometric(solid, p);
            INFO("trial " << trial << " objective " << r.objective << " bound " << r.lowerBound);
            REQUIRE(r.lowerBound <= r.objective * (1 + 1e-9) + 1e-12);
            REQUIRE(geometricObjective(solid, p, {}, r.dose) ==
                    Approx(r.objective).epsilon(1e-7).margin(1e-9));
            GeometricPatternLp full(solid, p, {});
            double bestGreedy = INFINITY, bestGreedyLight = 0;
            const int window = longestGap(p), starts = DlpGeometricOptions{}.startGaps;
            for (int q = 0; q < window + 6; ++q) {
                const bool greedy = q < window, start = greedy && q + 1 > window - starts;
                const std::vector<uint8_t> pattern =
                    greedy ? greedyPattern(solid, p, q + 1) : randomPattern(rng, solid, 0.3);
                std::vector<double> dose;
                const double value = full.solve(pattern, dose);
                if (std::isinf(value)) continue;
                ++solvedPatterns;
                REQUIRE(r.lowerBound <= value * (1 + 1e-9) + 1e-12);
                if (start && value < bestGreedy)
                    bestGreedy = value, bestGreedyLight = lightPerEc(p, dose);
            }
            if (std::isfinite(bestGreedy))
                REQUIRE(r.objective <= bestGreedy + 1e-4 * bestGreedyLight + 1e-9);
        }
    REQUIRE(solvedPatterns > 100);
}

TEST_CASE("geometric greedy start patterns keep Eq. 10", "[optimise]") {
    std::mt19937 rng(5);
    for (Bonding bonding : {Bonding::OwnLayer, Bonding::RunBottom})
        for (int trial = 0; trial < 50; ++trial) {
            const DlpColumnProblem p = seedResin(bonding);
            const std::vector<uint8_t> solid = randomColumn(rng, 40 + size_t(trial) * 3);
            for (int gap = 1; gap <= longestGap(p); ++gap) {
                const std::vector<uint8_t> pattern = greedyPattern(solid, p, gap);
                std::vector<double> lo, hi;
                REQUIRE(exposureBounds(pattern, solid, p, lo, hi));  // no void exposed either
                for (const auto& [bottom, top] : solidRuns(solid)) REQUIRE(pattern[top]);
            }
        }
}
