// The exact column solver: active-set bounded least squares against Eq. 9's projected gradient
// descent and the KKT conditions; branch and bound against exhaustive enumeration; Eq. 10 on
// every non-null dose of the optimum.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "dlp_test_support.h"
#include "vpsim/optimise/dlp/pattern_search.h"
#include "vpsim/optimise/solvers/bounded_least_squares.h"

using namespace vpsim::optimise;
using vpsim::test::seedResin;

namespace {

/// d_k >= bonding dose for its n_z, read independently of the solver from the dose vector.
void requireEq10(const std::vector<uint8_t>& solid, const std::vector<double>& d,
                 const DlpColumnProblem& p) {
    const double gel = -std::log1p(-p.gelPoint) / p.rateConstant;
    for (size_t k = 0; k < d.size(); ++k) {
        if (!solid[k]) REQUIRE(d[k] == 0.0);
        if (d[k] == 0.0) continue;
        REQUIRE(d[k] <= p.maxDose);
        size_t j = k;  // previous exposure below in the run, or the run's bottom
        bool found = false;
        while (j > 0 && solid[j - 1]) {
            --j;
            if (d[j] > 0.0) {
                found = true;
                break;
            }
        }
        int nz = found ? int(k - j) : (p.bonding == Bonding::RunBottom ? int(k - j + 1) : 1);
        INFO("layer " << k << " n_z " << nz);
        REQUIRE(d[k] >= gel * std::exp(p.attenuation * p.layerThickness * nz) * (1 - 1e-12));
    }
}

}  // namespace

TEST_CASE("BLS: active set equals projected gradient descent (Eq. 9) to 1e-9 in F", "[optimise]") {
    // Random targets and boxes, some with active bounds at both ends. PGD is run to a 1e-13
    // step tolerance (its linear rate ~ 1 - 1/214 needs ~1e4 steps); agreement in F to 1e-9
    // relative is the criterion.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int trial = 0; trial < 20; ++trial) {
        const size_t n = 5 + trial * 2;
        Transmission t{n, 0.528, std::exp(-0.05 / 0.366)};
        std::vector<double> target(n), lo(n), hi(n);
        for (size_t k = 0; k < n; ++k) {
            target[k] = u(rng) < 0.3 ? 5.5 : -3.0 * u(rng);
            lo[k] = u(rng) < 0.2 ? 0.0 : 0.6 * u(rng);
            hi[k] = lo[k] + (u(rng) < 0.2 ? 0.0 : 1.3 * u(rng));
        }
        BoundedLeastSquaresResult exact = solveBoundedLeastSquares(t, target, lo, hi);
        BoundedLeastSquaresResult ref = solveByProjectedGradient(t, target, lo, hi, 400000, 1e-15);
        REQUIRE(exact.converged);
        INFO("n " << n << " active-set F " << exact.objective << " PGD F " << ref.objective);
        REQUIRE(exact.objective <= ref.objective * (1 + 1e-9) + 1e-14);
        REQUIRE(exact.objective == Approx(ref.objective).epsilon(1e-9).margin(1e-14));
        // KKT at the exact solution.
        std::vector<double> r = t.apply(exact.dose);
        for (size_t k = 0; k < n; ++k) r[k] -= target[k];
        std::vector<double> g = t.applyTransposed(r);
        for (size_t k = 0; k < n; ++k) {
            if (lo[k] == hi[k]) continue;
            if (exact.dose[k] <= lo[k])
                REQUIRE(g[k] >= -1e-9);
            else if (exact.dose[k] >= hi[k])
                REQUIRE(g[k] <= 1e-9);
            else
                REQUIRE(std::abs(g[k]) <= 1e-9);
        }
    }
}

TEST_CASE("BLS: unbounded optimum is the bidiagonal inverse", "[optimise]") {
    // F = 0 at d = T^-1 t when the box is wide: d_p = (r t_{p+1} - t_p) / K (tolerance 1e-12).
    const size_t n = 40;
    Transmission t{n, 0.5, 0.8};
    std::vector<double> target(n, -3.0), lo(n, -100.0), hi(n, 100.0);
    BoundedLeastSquaresResult s = solveBoundedLeastSquares(t, target, lo, hi);
    REQUIRE(s.objective < 1e-20);
    for (size_t p = 0; p + 1 < n; ++p)
        REQUIRE(s.dose[p] == Approx((0.8 * target[p + 1] - target[p]) / 0.5).epsilon(1e-12));
}

TEST_CASE("DLP exact: branch and bound equals enumeration on small columns", "[optimise]") {
    // Random solid/void profiles of up to 12 solid layers in 18: every pattern enumerated is the
    // ground truth. Tolerance 1e-9 relative (both use the same exact per-pattern solve).
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (Bonding bonding : {Bonding::RunBottom, Bonding::OwnLayer}) {
        for (int trial = 0; trial < 12; ++trial) {
            std::vector<uint8_t> solid(18, 0);
            int count = 0;
            for (size_t k = 0; k < solid.size(); ++k)
                if (count < 12 && u(rng) < 0.6) solid[k] = 1, ++count;
            DlpColumnProblem p = seedResin(trial % 2 ? 1.3 : 2.6, bonding);
            p.penalty = trial % 3 == 0 ? 0.0 : 5.5;
            DlpSearchResult brute = enumerateColumnPatterns(solid, p);
            DlpSearchOptions o;
            o.enumerationLimit = 0;
            o.maxNodes = 100000;
            DlpSearchResult bb = branchAndBoundColumn(solid, p, o);
            INFO("trial " << trial << " nodes " << bb.nodes << " of " << brute.nodes);
            REQUIRE(bb.gap <= 1e-9);
            REQUIRE(bb.best.objective == Approx(brute.best.objective).epsilon(1e-9));
            requireEq10(solid, bb.best.dose, p);
            requireEq10(solid, brute.best.dose, p);
        }
    }
}

TEST_CASE("DLP exact: seed 001 hole column, Eq. 10 on every dose, never worse than heuristic",
          "[optimise]") {
    // The case-1 column through both holes (220 layers): 40 solid, 60 void, 40 solid, 30 void,
    // 50 solid. The exact search must respect Eq. 10 and not lose to the old skip search.
    std::vector<uint8_t> solid(220, 0);
    for (int k = 0; k < 40; ++k) solid[k] = 1;
    for (int k = 100; k < 140; ++k) solid[k] = 1;
    for (int k = 170; k < 220; ++k) solid[k] = 1;
    for (Bonding bonding : {Bonding::RunBottom, Bonding::OwnLayer}) {
        DlpColumnProblem p = seedResin(1.3, bonding);
        DlpSearchResult r = solveColumnExactly(solid, p);
        INFO("nodes " << r.nodes << " gap " << r.gap);
        requireEq10(solid, r.best.dose, p);
        REQUIRE(r.lowerBound <= r.best.objective);
        if (bonding == Bonding::RunBottom)
            REQUIRE(r.best.objective <= optimiseColumnDoses(solid, p).objective * (1 + 1e-9));
    }
}
