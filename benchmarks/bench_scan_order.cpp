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
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vpsim/plan/aces.h"
#include "vpsim/plan/part_order.h"
#include "vpsim/plan/scanner.h"
#include "vpsim/plan/trajectory.h"

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
    auto path = std::filesystem::path(__FILE__).parent_path() /
                "../tests/data/reference/seed002_table3_jump_ordering.csv";
    std::ifstream in(path);
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
          {"target_s", 1.0}}}};
    std::cout << out.dump(2) << "\n";
    return 0;
}
