#pragma once
/// @file
/// Order of the parts of one layer (seed 002 Section 4): an open path through all parts, any
/// part first, minimising the sum of jump times cost(i, j) from part i's last mark to part j's
/// first (asymmetric: a jump starts with the last mark's velocity). Methods: nearest neighbour
/// from every start (seed 002's baseline), exact dynamic programming over subsets (Held-Karp,
/// the exact form of seed 002's DP with its "keep only the fastest path into each part" rule),
/// and for larger layers the best nearest-neighbour paths improved by Or-opt and 2-opt moves.
/// Seed 000's ant colony (Eq. 20) is not implemented: the improved heuristic is deterministic,
/// its gap to the exact optimum on the sizes the DP reaches is measured in
/// benchmarks/bench_scan_order.cpp.

#include <string>
#include <vector>

namespace vpsim::plan {

/// Job key `plan.order`.
enum class OrderMethod { Auto, Exact, Heuristic, NearestNeighbour, AsSliced };

/// @throw InputError naming `key` for anything but auto | exact | heuristic |
/// nearest-neighbour | as-sliced
OrderMethod parseOrderMethod(const std::string& text, const std::string& key = "plan.order",
                             const std::string& file = "");
std::string toString(OrderMethod method);

/// Square matrix of jump times (s), row = from, column = to.
struct CostMatrix {
    int n = 0;
    std::vector<double> values;  ///< row-major n x n
    explicit CostMatrix(int size = 0) : n(size), values(size_t(size) * size, 0.0) {}
    double operator()(int from, int to) const { return values[size_t(from) * n + to]; }
    double& operator()(int from, int to) { return values[size_t(from) * n + to]; }
};

struct OrderResult {
    std::vector<int> order;           ///< part indices in scan order
    double cost = 0;                  ///< s, sum of the jumps along `order`
    std::string method;               ///< the method that ran ("exact", "heuristic", ...)
    bool provenOptimal = false;       ///< true for the exact DP (and for n <= 2)
    double nearestNeighbourCost = 0;  ///< s, best-start nearest neighbour on the same costs
};

/// Largest layer `auto` solves exactly (2^16 x 16 states: milliseconds).
constexpr int AUTO_EXACT_LIMIT = 16;
/// Largest layer `exact` accepts (20 x 2^19 double states: 84 MB, about a second).
constexpr int MAX_EXACT_PARTS = 20;

/// Sum of cost(order[k], order[k+1]).
double pathCost(const CostMatrix& cost, const std::vector<int>& order);
/// Nearest neighbour from every start; the cheapest path.
OrderResult nearestNeighbourOrder(const CostMatrix& cost);
/// Held-Karp over subsets in double, free start and end. @throw InputError above MAX_EXACT_PARTS
/// parts
OrderResult exactOrder(const CostMatrix& cost);
/// Or-opt (segments of 1-3 parts moved, either way round) and 2-opt (segment reversal) from the
/// best few nearest-neighbour paths until no move improves.
OrderResult heuristicOrder(const CostMatrix& cost);
/// Dispatches on `method`; Auto is exact up to AUTO_EXACT_LIMIT parts and heuristic beyond.
/// Every result carries the best-start nearest-neighbour cost for comparison.
OrderResult orderParts(const CostMatrix& cost, OrderMethod method);

}  // namespace vpsim::plan
