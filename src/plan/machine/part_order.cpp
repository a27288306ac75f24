#include "vpsim/plan/machine/part_order.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "vpsim/core/error.h"

namespace vpsim::plan {
namespace {

OrderResult trivialOrder(const CostMatrix& cost, const std::string& method) {
    OrderResult result;
    result.order.resize(size_t(cost.n));
    std::iota(result.order.begin(), result.order.end(), 0);
    if (cost.n == 2 && cost(1, 0) < cost(0, 1)) std::swap(result.order[0], result.order[1]);
    result.cost = pathCost(cost, result.order);
    result.method = method;
    result.provenOptimal = true;
    result.nearestNeighbourCost = result.cost;
    return result;
}

std::vector<int> nearestNeighbourFrom(const CostMatrix& cost, int start) {
    std::vector<int> order{start};
    std::vector<char> visited(size_t(cost.n), 0);
    visited[size_t(start)] = 1;
    for (int step = 1; step < cost.n; ++step) {
        int from = order.back(), next = -1;
        for (int j = 0; j < cost.n; ++j)
            if (!visited[size_t(j)] && (next < 0 || cost(from, j) < cost(from, next))) next = j;
        visited[size_t(next)] = 1;
        order.push_back(next);
    }
    return order;
}

/// Local search on an open path. The path is held as [D, p0..p(n-1), D] with a dummy part D whose
/// jumps cost nothing, so the free start and end become ordinary neighbours and every move has
/// both neighbours.
class LocalSearch {
public:
    LocalSearch(const CostMatrix& cost, const std::vector<int>& order) : mCost(cost) {
        mPath.push_back(-1);
        mPath.insert(mPath.end(), order.begin(), order.end());
        mPath.push_back(-1);
        prefixSums();
    }

    void run() {
        for (int pass = 0; pass < 1000; ++pass)
            if (!orOptPass() && !twoOptPass()) break;
    }

    std::vector<int> order() const { return {mPath.begin() + 1, mPath.end() - 1}; }

private:
    double c(int a, int b) const { return a < 0 || b < 0 ? 0.0 : mCost(a, b); }
    double at(int i, int j) const { return c(mPath[size_t(i)], mPath[size_t(j)]); }
    // Cost of positions i..j walked forwards / backwards.
    double forward(int i, int j) const { return mF[size_t(j)] - mF[size_t(i)]; }
    double backward(int i, int j) const { return mB[size_t(j)] - mB[size_t(i)]; }

    void prefixSums() {
        mF.assign(mPath.size(), 0.0);
        mB.assign(mPath.size(), 0.0);
        for (size_t k = 0; k + 1 < mPath.size(); ++k) {
            mF[k + 1] = mF[k] + at(int(k), int(k + 1));
            mB[k + 1] = mB[k] + at(int(k + 1), int(k));
        }
    }

    static constexpr double EPS = 1e-12;

    bool twoOptPass() {
        bool improved = false;
        const int n = int(mPath.size()) - 2;
        for (int i = 1; i < n; ++i)
            for (int j = i + 1; j <= n; ++j) {
                double delta = at(i - 1, j) + at(i, j + 1) + backward(i, j) - at(i - 1, i) -
                               at(j, j + 1) - forward(i, j);
                if (delta < -EPS) {
                    std::reverse(mPath.begin() + i, mPath.begin() + j + 1);
                    prefixSums();
                    improved = true;
                }
            }
        return improved;
    }

    bool orOptPass() {
        bool improved = false;
        const int n = int(mPath.size()) - 2;
        for (int length = 1; length <= 3; ++length)
            for (int i = 1; i + length - 1 <= n; ++i) {
                const int e = i + length - 1;
                const double gain = at(i - 1, i) + at(e, e + 1) - at(i - 1, e + 1);
                const double flip = backward(i, e) - forward(i, e);
                for (int k = 0; k <= n; ++k) {
                    if (k >= i - 1 && k <= e) continue;
                    const double base = -at(k, k + 1) - gain;
                    const double fwd = at(k, i) + at(e, k + 1) + base;
                    const double rev = at(k, e) + at(i, k + 1) + flip + base;
                    if (fwd < -EPS || rev < -EPS) {
                        move(i, e, k, rev < fwd);
                        improved = true;
                        break;
                    }
                }
            }
        return improved;
    }

    /// Moves positions i..e between positions k and k+1, reversed if asked.
    void move(int i, int e, int k, bool reversed) {
        std::vector<int> segment(mPath.begin() + i, mPath.begin() + e + 1);
        if (reversed) std::reverse(segment.begin(), segment.end());
        std::vector<int> path;
        path.reserve(mPath.size());
        for (int p = 0; p < int(mPath.size()); ++p) {
            if (p >= i && p <= e) continue;
            path.push_back(mPath[size_t(p)]);
            if (p == k) path.insert(path.end(), segment.begin(), segment.end());
        }
        mPath = std::move(path);
        prefixSums();
    }

    const CostMatrix& mCost;
    std::vector<int> mPath;
    std::vector<double> mF, mB;
};

}  // namespace

OrderMethod parseOrderMethod(const std::string& text, const std::string& key,
                             const std::string& file) {
    if (text == "auto") return OrderMethod::Auto;
    if (text == "exact") return OrderMethod::Exact;
    if (text == "heuristic") return OrderMethod::Heuristic;
    if (text == "nearest-neighbour") return OrderMethod::NearestNeighbour;
    if (text == "as-sliced") return OrderMethod::AsSliced;
    throw InputError("'" + text +
                         "' is not an ordering (auto, exact, heuristic, nearest-neighbour, "
                         "as-sliced)",
                     file, key);
}

std::string toString(OrderMethod method) {
    switch (method) {
        case OrderMethod::Auto: return "auto";
        case OrderMethod::Exact: return "exact";
        case OrderMethod::Heuristic: return "heuristic";
        case OrderMethod::NearestNeighbour: return "nearest-neighbour";
        case OrderMethod::AsSliced: return "as-sliced";
    }
    return "auto";
}

double pathCost(const CostMatrix& cost, const std::vector<int>& order) {
    double sum = 0;
    for (size_t k = 0; k + 1 < order.size(); ++k) sum += cost(order[k], order[k + 1]);
    return sum;
}

OrderResult nearestNeighbourOrder(const CostMatrix& cost) {
    if (cost.n <= 1) return trivialOrder(cost, "nearest-neighbour");
    OrderResult best;
    best.cost = std::numeric_limits<double>::infinity();
    for (int start = 0; start < cost.n; ++start) {
        std::vector<int> order = nearestNeighbourFrom(cost, start);
        double c = pathCost(cost, order);
        if (c < best.cost) best.order = std::move(order), best.cost = c;
    }
    best.method = "nearest-neighbour";
    best.nearestNeighbourCost = best.cost;
    return best;
}

OrderResult exactOrder(const CostMatrix& cost) {
    const int n = cost.n;
    if (n > MAX_EXACT_PARTS)
        throw InputError("exact ordering handles at most " + std::to_string(MAX_EXACT_PARTS) +
                             " parts per layer, this layer has " + std::to_string(n) +
                             " (use plan.order = auto or heuristic)",
                         "", "plan.order");
    if (n <= 2) return trivialOrder(cost, "exact");
    // dp[j][rest]: cheapest path visiting {j} + `rest` and ending at j, in double (a float table
    // rounds path costs to 6e-8 relative and can return a near-tie that is not optimal). `rest`
    // is the visited set with bit j squeezed out, so each row holds 2^(n-1) entries: n 2^(n-1)
    // doubles, the memory of the n 2^n floats this used to keep (20 parts: 84 MB).
    const size_t rows = size_t(1) << (n - 1);
    const double inf = std::numeric_limits<double>::infinity();
    auto squeeze = [](size_t mask, int j) {
        const size_t low = mask & ((size_t(1) << j) - 1);
        return low | (mask >> (j + 1)) << j;
    };
    std::vector<double> dp(rows * size_t(n), inf);
    auto at = [&](size_t mask, int j) -> double& {
        return dp[size_t(j) * rows + squeeze(mask, j)];
    };
    for (int j = 0; j < n; ++j) at(size_t(1) << j, j) = 0.0;
    const size_t states = size_t(1) << n;
    for (size_t mask = 1; mask < states; ++mask)
        for (int j = 0; j < n; ++j) {
            if (!(mask >> j & 1)) continue;
            const double here = at(mask, j);
            if (here == inf) continue;
            for (int k = 0; k < n; ++k) {
                if (mask >> k & 1) continue;
                double& next = at(mask | size_t(1) << k, k);
                next = std::min(next, here + cost(j, k));
            }
        }
    size_t mask = states - 1;
    int last = 0;
    for (int j = 1; j < n; ++j)
        if (at(mask, j) < at(mask, last)) last = j;
    std::vector<int> order{last};
    // The backtrack repeats the same double sums, so it finds a predecessor exactly.
    while (mask != (size_t(1) << last)) {
        const size_t prev = mask ^ (size_t(1) << last);
        const double target = at(mask, last);
        int from = -1;
        for (int i = 0; i < n && from < 0; ++i)
            if (prev >> i & 1 && at(prev, i) + cost(i, last) == target) from = i;
        if (from < 0) throw std::logic_error("Held-Karp backtrack lost its path");
        order.push_back(from);
        mask = prev, last = from;
    }
    std::reverse(order.begin(), order.end());
    OrderResult result;
    result.order = std::move(order);
    result.cost = pathCost(cost, result.order);
    result.method = "exact";
    result.provenOptimal = true;
    return result;
}

OrderResult heuristicOrder(const CostMatrix& cost) {
    if (cost.n <= 2) return trivialOrder(cost, "heuristic");
    // Improve the best few nearest-neighbour starts (distinct local optima), keep the best.
    std::vector<std::pair<double, int>> starts;
    for (int s = 0; s < cost.n; ++s)
        starts.push_back({pathCost(cost, nearestNeighbourFrom(cost, s)), s});
    std::sort(starts.begin(), starts.end());
    const int tries = std::min<int>(cost.n, cost.n > 300 ? 1 : cost.n > 100 ? 3 : 6);
    OrderResult best;
    best.cost = std::numeric_limits<double>::infinity();
    for (int t = 0; t < tries; ++t) {
        LocalSearch search(cost, nearestNeighbourFrom(cost, starts[size_t(t)].second));
        search.run();
        std::vector<int> order = search.order();
        double c = pathCost(cost, order);
        if (c < best.cost) best.order = std::move(order), best.cost = c;
    }
    best.method = "heuristic";
    best.nearestNeighbourCost = starts[0].first;
    return best;
}

OrderResult orderParts(const CostMatrix& cost, OrderMethod method) {
    const bool heuristic = method == OrderMethod::Heuristic ||
                           (method == OrderMethod::Auto && cost.n > AUTO_EXACT_LIMIT);
    if (heuristic && cost.n > 2) return heuristicOrder(cost);  // it runs every NN start itself
    OrderResult nn = nearestNeighbourOrder(cost);
    OrderResult result;
    switch (method) {
        case OrderMethod::AsSliced:
            result.order.resize(size_t(cost.n));
            std::iota(result.order.begin(), result.order.end(), 0);
            result.cost = pathCost(cost, result.order);
            result.method = "as-sliced";
            result.provenOptimal = cost.n <= 1;
            break;
        case OrderMethod::NearestNeighbour: result = nn; break;
        case OrderMethod::Exact: result = exactOrder(cost); break;
        case OrderMethod::Heuristic: result = heuristicOrder(cost); break;
        case OrderMethod::Auto:
            result = cost.n <= AUTO_EXACT_LIMIT ? exactOrder(cost) : heuristicOrder(cost);
            break;
    }
    result.nearestNeighbourCost = nn.cost;
    return result;
}

}  // namespace vpsim::plan
