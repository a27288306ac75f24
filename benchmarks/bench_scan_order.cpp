// Ordering of layer parts on seed-002-like layers (Section 4, Table 3): S = 5, 20, 50, 200 small
// parts placed at random in 1 cm^2 (fixed seed; the smaller layers are subsamples of the 200, as
// in the seed's Fig. 8). Seed 002's kinematics: machine 2 m/s and 20 m/s^2, every jump starting
// with vx = 0, vy = 0.3 m/s (the process speed) at the part's hatch end and ending at rest on the
// next part's contour point closest to its hatch start. Prints JSON: for each S and method the
// jump time of the order and the compute time, beside Table 3's DP and NN times; the gain over
// best-start nearest neighbour measured here beside the seed's; and the time to build a whole
// 200-part layer trajectory (hatching, grouping, cost matrix, ordering). Targets (issue 12):
// ordering 200 parts under 1 s.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vpsim/plan/aces/aces.h"
#include "vpsim/plan/machine/part_order.h"
#include "vpsim/plan/machine/scanner.h"
#include "vpsim/plan/machine/trajectory.h"

using namespace vpsim;
using namespace vpsim::plan;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double PART = 0.3;  // mm, side of a square layer part

struct Table3Row {
    double dp = 0, nn = 0, relative = 0;
    std::string optimality;
};

std::map<int, Table3Row> readTable3() {
    std::map<int, Table3Row> rows;
    // The source tree's copy: beside this file (absolute __FILE__) or from the repository root.
    const std::string name = "tests/data/reference/seed002_table3_jump_ordering.csv";
    std::ifstream in;
    for (const auto& candidate : {std::filesystem::path(__FILE__).parent_path() / ".." / name,
                                  std::filesystem::path(name), std::filesystem::path("..") / name})
        if (std::filesystem::exists(candidate)) {
            in.open(candidate);
            break;
        }
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#' || line.rfind("parts", 0) == 0) continue;
        std::stringstream s(line);
        std::string f[6];
        for (auto& field : f) std::getline(s, field, ',');
        rows[std::stoi(f[0])] = {std::stod(f[1]), std::stod(f[2]), std::stod(f[3]), f[5]};
    }
    return rows;
}

/// Hatch start (lower left corner) of every part, non-overlapping, in 10 x 10 mm.
std::vector<glm::dvec2> partCorners(int count, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 10.0 - PART);
    std::vector<glm::dvec2> corners;
    while (int(corners.size()) < count) {
        glm::dvec2 p{u(rng), u(rng)};
        bool clear = true;
        for (const auto& q : corners)
            clear = clear && (std::abs(p.x - q.x) > 1.5 * PART || std::abs(p.y - q.y) > 1.5 * PART);
        if (clear) corners.push_back(p);
    }
    return corners;
}

CostMatrix seedCosts(const std::vector<glm::dvec2>& corners, int count) {
    const AxisLimits machine{2000.0, 20000.0};
    CostMatrix cost(count);
    for (int i = 0; i < count; ++i)
        for (int j = 0; j < count; ++j)
            if (i != j)
                cost(i, j) = jumpTime(corners[size_t(i)] + glm::dvec2{PART, PART},
                                      corners[size_t(j)], {0.0, 300.0}, machine);
    return cost;
}

/// Seed 000's ant colony (Eq. 20), measured here to decide whether it earns a place in the library
/// (issue 12: only if it beats the exact and improved orderings). An ant at i picks j with
/// probability tau_ij^alpha eta_ij^beta / sum (eta = 1/cost: visibility in jump time); every ant
/// leaves Q / cost_ij on the jumps it made; tau <- rho tau + sum delta tau. Free start.
OrderResult antColony(const CostMatrix& cost, int ants, int iterations, unsigned seed) {
    const int n = cost.n;
    const double alpha = 1.0, beta = 3.0, rho = 0.5, q = 1e-3;
    std::vector<double> tau(size_t(n) * n, 1.0), eta(size_t(n) * n, 0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            if (i != j) eta[size_t(i) * n + j] = std::pow(1.0 / std::max(cost(i, j), 1e-9), beta);
    std::mt19937 rng(seed);
    OrderResult best;
    best.cost = INFINITY;
    std::vector<double> weight(static_cast<size_t>(n));
    for (int it = 0; it < iterations; ++it) {
        std::vector<double> deposit(size_t(n) * n, 0.0);
        for (int a = 0; a < ants; ++a) {
            std::vector<char> seen(size_t(n), 0);
            std::vector<int> order{int(rng() % unsigned(n))};
            seen[size_t(order[0])] = 1;
            while (int(order.size()) < n) {
                const int i = order.back();
                double total = 0;
                for (int j = 0; j < n; ++j)
                    total += weight[size_t(j)] =
                        seen[size_t(j)] ? 0.0 : tau[size_t(i) * n + j] * eta[size_t(i) * n + j];
                double pick = std::uniform_real_distribution<double>(0.0, total)(rng);
                int next = -1;
                for (int j = 0; j < n && next < 0; ++j)
                    if (!seen[size_t(j)] && (pick -= weight[size_t(j)]) <= 0) next = j;
                if (next < 0)
                    for (int j = n - 1; j >= 0 && next < 0; --j)
                        if (!seen[size_t(j)]) next = j;
                seen[size_t(next)] = 1;
                order.push_back(next);
            }
            for (size_t k = 0; k + 1 < order.size(); ++k)
                deposit[size_t(order[k]) * n + order[k + 1]] +=
                    q / std::max(cost(order[k], order[k + 1]), 1e-9);
            const double c = pathCost(cost, order);
            if (c < best.cost) best.cost = c, best.order = order;
        }
        for (size_t k = 0; k < tau.size(); ++k) tau[k] = rho * tau[k] + deposit[k];
        (void)alpha;  // alpha = 1: tau enters linearly
    }
    best.method = "ant-colony";
    return best;
}

template <class F>
std::pair<OrderResult, double> timed(F&& f) {
    auto t0 = Clock::now();
    OrderResult r = f();
    return {r, std::chrono::duration<double>(Clock::now() - t0).count()};
}

}  // namespace

int main() {
    std::mt19937 rng(2002);
    const std::vector<glm::dvec2> corners = partCorners(200, rng);
    const auto table3 = readTable3();
    nlohmann::json layers = nlohmann::json::array();
    for (int count : {5, 20, 50, 200}) {
        const CostMatrix cost = seedCosts(corners, count);
        nlohmann::json methods;
        double nn = 0, best = INFINITY;
        for (OrderMethod method : {OrderMethod::AsSliced, OrderMethod::NearestNeighbour,
                                   OrderMethod::Heuristic, OrderMethod::Exact, OrderMethod::Auto}) {
            if (method == OrderMethod::Exact && count > MAX_EXACT_PARTS) continue;
            auto [result, seconds] = timed([&] { return orderParts(cost, method); });
            methods[toString(method)] = {{"jump_time_s", result.cost},
                                         {"compute_s", seconds},
                                         {"proven_optimal", result.provenOptimal}};
            nn = result.nearestNeighbourCost;
            if (method != OrderMethod::AsSliced) best = std::min(best, result.cost);
        }
        {
            auto [aco, seconds] = timed([&] { return antColony(cost, 20, 100, 7); });
            methods["ant-colony (seed 000 Eq. 20, 20 ants x 100 rounds)"] = {
                {"jump_time_s", aco.cost}, {"compute_s", seconds}, {"proven_optimal", false}};
        }
        nlohmann::json row = {{"parts", count},
                              {"methods", methods},
                              {"best_jump_time_s", best},
                              {"best_start_nn_jump_time_s", nn},
                              {"gain_over_nn_pct", 100.0 * (nn - best) / best}};
        if (table3.count(count)) {
            const Table3Row& t = table3.at(count);
            row["seed002_table3"] = {{"dp_time_s", t.dp},
                                     {"nn_time_s", t.nn},
                                     {"gain_over_nn_pct", t.relative},
                                     {"optimality", t.optimality}};
        }
        layers.push_back(row);
    }
    // A whole 200-part layer through the trajectory builder (hatched along y at 300 mm/s).
    geometry::PolygonSet region;
    for (const auto& c : corners)
        region = region.unite(geometry::PolygonSet::rectangle(c, c + glm::dvec2{PART, PART}));
    LayerPlan layer;
    layer.vectors = hatchRegion(region, 0.05, M_PI / 2, 100, 300);
    auto t0 = Clock::now();
    LayerTrajectory trajectory = buildLayerTrajectory(layer, 100, TrajectoryOptions{}, &region);
    const double buildSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    TrajectoryOptions free;
    free.chooseEntry = true;
    LayerTrajectory freeEntry = buildLayerTrajectory(layer, 100, free, &region);
    auto allJumps = [](const LayerTrajectory& t) {
        double sum = 0;
        const ScanMove* last = nullptr;
        for (const ScanMove& m : t.moves) {
            if (!m.laserOn && last)
                sum += jumpTime({m.x0, m.y0}, {m.x1, m.y1}, endVelocity(*last), {2000, 20000});
            last = m.laserOn ? &m : nullptr;
        }
        return sum;
    };
    nlohmann::json out = {
        {"benchmark", "scan_order"},
        {"setting", "seed 002 Sec. 4: 1 cm^2, machine 2 m/s 20 m/s^2, jumps start at vy = 0.3 m/s"},
        {"layers", layers},
        {"layer_trajectory_200_parts",
         {{"parts", trajectory.parts},
          {"vectors", layer.vectors.size()},
          {"method", trajectory.order.method},
          {"jump_time_between_parts_s", trajectory.order.cost},
          {"best_start_nn_s", trajectory.order.nearestNeighbourCost},
          {"build_s", buildSeconds},
          {"all_jumps_s", allJumps(trajectory)},
          {"entry_points_chosen",
           {{"reversed_parts", freeEntry.reversedParts},
            {"jump_time_between_parts_s", freeEntry.order.cost},
            {"all_jumps_s", allJumps(freeEntry)}}},
          {"target_s", 1.0}}}};
    std::cout << out.dump(2) << "\n";
    return 0;
}
