// Ordering of layer parts: the exact DP equals brute force; heuristics lie between the optimum
// and best-start nearest neighbour.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "vpsim/core/error.h"
#include "vpsim/plan/machine/part_order.h"
#include "vpsim/plan/machine/scanner.h"

using namespace vpsim;
using namespace vpsim::plan;

namespace {

double bruteForce(const CostMatrix& cost) {
    std::vector<int> order(size_t(cost.n));
    std::iota(order.begin(), order.end(), 0);
    double best = INFINITY;
    do best = std::min(best, pathCost(cost, order));
    while (std::next_permutation(order.begin(), order.end()));
    return best;
}

CostMatrix randomMatrix(int n, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.01, 1.0);
    CostMatrix cost(n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) cost(i, j) = i == j ? 0.0 : u(rng);
    return cost;
}

/// Seed 002's setting: parts in 10 x 10 mm, jumps starting at 300 mm/s along +y.
CostMatrix kinematicMatrix(int n, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 10.0);
    std::vector<glm::dvec2> p;
    for (int i = 0; i < n; ++i) p.push_back({u(rng), u(rng)});
    CostMatrix cost(n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            if (i != j) cost(i, j) = jumpTime(p[size_t(i)], p[size_t(j)], {0, 300}, {2000, 20000});
    return cost;
}

bool isPermutation(std::vector<int> order, int n) {
    std::sort(order.begin(), order.end());
    for (int i = 0; i < n; ++i)
        if (order.size() != size_t(n) || order[size_t(i)] != i) return false;
    return true;
}

}  // namespace

TEST_CASE("exact ordering equals brute force up to 8 parts", "[plan]") {
    std::mt19937 rng(12);
    for (int n = 1; n <= 8; ++n)
        for (int trial = 0; trial < 4; ++trial) {
            CostMatrix cost = trial % 2 ? randomMatrix(n, rng) : kinematicMatrix(n, rng);
            OrderResult exact = exactOrder(cost);
            INFO("n = " << n << ", trial " << trial);
            REQUIRE(isPermutation(exact.order, n));
            CHECK(exact.provenOptimal);
            CHECK(exact.cost == Approx(bruteForce(cost)).epsilon(1e-6));
            CHECK(exact.cost == Approx(pathCost(cost, exact.order)));
            OrderResult nn = nearestNeighbourOrder(cost);
            OrderResult heuristic = heuristicOrder(cost);
            REQUIRE(isPermutation(heuristic.order, n));
            CHECK(nn.cost >= exact.cost - 1e-9);
            CHECK(heuristic.cost >= exact.cost - 1e-9);
            CHECK(heuristic.cost <= nn.cost + 1e-12);
        }
}

// Held-Karp must be exact in double: on 7 parts whose jump costs differ only in the 7th digit
// (1 + 1e-6 u: every path costs about 6, so a float table, whose spacing there is 5e-7, cannot
// tell the best path from its near-ties), its path must cost what brute-force enumeration of all
// 5040 orders finds, to 1e-12 relative (double sums of 6 terms round at about 1e-15).
TEST_CASE("exact ordering equals brute force to 1e-12 on near-ties", "[plan]") {
    std::mt19937 rng(29);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int trial = 0; trial < 12; ++trial) {
        const int n = 7;
        CostMatrix cost(n);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                cost(i, j) = i == j           ? 0.0
                             : trial % 3 == 2 ? u(rng)  // plain random costs too
                                              : 1.0 + 1e-6 * u(rng);
        const double best = bruteForce(cost);
        const OrderResult exact = exactOrder(cost);
        INFO("trial " << trial << ": brute force " << best << ", Held-Karp " << exact.cost);
        REQUIRE(isPermutation(exact.order, n));
        CHECK(exact.provenOptimal);
        CHECK(std::abs(pathCost(cost, exact.order) - best) <= 1e-12 * best);
        CHECK(std::abs(exact.cost - best) <= 1e-12 * best);
    }
}

TEST_CASE("orderParts dispatches, reports nearest neighbour beside the result", "[plan]") {
    std::mt19937 rng(3);
    CostMatrix small = kinematicMatrix(10, rng), large = kinematicMatrix(40, rng);
    OrderResult a = orderParts(small, OrderMethod::Auto);
    CHECK(a.method == "exact");
    CHECK(a.provenOptimal);
    CHECK(a.nearestNeighbourCost >= a.cost - 1e-9);
    OrderResult b = orderParts(large, OrderMethod::Auto);
    CHECK(b.method == "heuristic");
    CHECK_FALSE(b.provenOptimal);
    CHECK(isPermutation(b.order, 40));
    CHECK(b.cost <= b.nearestNeighbourCost + 1e-12);
    OrderResult s = orderParts(large, OrderMethod::AsSliced);
    CHECK(s.order.front() == 0);
    CHECK(s.order.back() == 39);
    CHECK_THROWS_AS(orderParts(large, OrderMethod::Exact), InputError);
    CHECK(parseOrderMethod("nearest-neighbour") == OrderMethod::NearestNeighbour);
    CHECK_THROWS_WITH(parseOrderMethod("tsp"), Catch::Contains("plan.order"));
}
