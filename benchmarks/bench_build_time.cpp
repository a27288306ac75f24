// Build-time estimate (seed 002 Eq. 1-4, plan/build_time.h) of a job with 1e6 scan vectors:
// 25 layers of a 20 x 20 grid of 2 mm squares hatched at 20 um (40,000 vectors per layer).
// Prints JSON: the estimate's compute time on the plan order and on built trajectories, the
// trajectory build time for one layer, and in the same run the floor of summing every vector's
// length / speed once. Target (issue 12): the estimate under 1 s.
#include <chrono>
#include <cmath>
#include <iostream>

#include <nlohmann/json.hpp>

#include "vpsim/plan/aces/aces.h"
#include "vpsim/plan/machine/build_time.h"
#include "vpsim/plan/machine/part_grouping.h"
#include "vpsim/plan/machine/trajectory.h"

using namespace vpsim;
using namespace vpsim::plan;
using Clock = std::chrono::steady_clock;

namespace {
double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}
}  // namespace

int main() {
    geometry::PolygonSet region;
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 20; ++j)
            region = region.unite(
                geometry::PolygonSet::rectangle({2.5 * i, 2.5 * j}, {2.5 * i + 2, 2.5 * j + 2}));
    ScanPlan plan;
    LayerPlan layer;
    layer.vectors = hatchRegion(region, 0.02, 0.0, 100, 300);
    for (int k = 0; k < 25; ++k) {
        layer.z = 0.05 * (k + 1);
        plan.layers.push_back(layer);
    }
    size_t vectors = 0;
    for (const auto& l : plan.layers) vectors += l.vectors.size();

    auto t0 = Clock::now();
    double floor = 0;
    for (const auto& l : plan.layers)
        for (const auto& v : l.vectors) floor += std::hypot(v.x1 - v.x0, v.y1 - v.y0) / v.speed;
    const double floorSeconds = since(t0);

    BuildTimeOptions options;
    options.recoatTime = 10.0;
    t0 = Clock::now();
    BuildTime planOrder = estimateBuildTime(plan, options);
    const double planOrderSeconds = since(t0);

    t0 = Clock::now();
    LayerTrajectory one = buildLayerTrajectory(plan.layers[0], 100, TrajectoryOptions{}, &region);
    const double trajectorySeconds = since(t0);
    t0 = Clock::now();
    PartGroups groups = groupLayerParts(plan.layers[0], 0.2, &region);
    const double groupSeconds = since(t0);
    for (auto& l : plan.layers) l.trajectory = one.moves;
    t0 = Clock::now();
    BuildTime ordered = estimateBuildTime(plan, options);
    const double orderedSeconds = since(t0);

    nlohmann::json out = {{"benchmark", "build_time"},
                          {"scan_vectors", vectors},
                          {"layers", plan.layers.size()},
                          {"estimate_plan_order_s", planOrderSeconds},
                          {"estimate_trajectories_s", orderedSeconds},
                          {"target_s", 1.0},
                          {"floor_sum_lengths_s", floorSeconds},
                          {"estimate_over_floor", planOrderSeconds / floorSeconds},
                          {"mark_time_check_s", {{"floor", floor}, {"model", planOrder.sum.mark}}},
                          {"build_time_plan_order", planOrder.toJson()["total"]},
                          {"build_time_ordered", ordered.toJson()["total"]},
                          {"breakdown_ordered",
                           {{"mark", ordered.sum.mark},
                            {"jump", ordered.sum.jump},
                            {"delays", ordered.sum.delays},
                            {"recoat", ordered.sum.recoat}}},
                          {"trajectory_one_layer",
                           {{"vectors", plan.layers[0].vectors.size()},
                            {"parts", one.parts},
                            {"method", one.order.method},
                            {"build_s", trajectorySeconds},
                            {"grouping_s", groupSeconds},
                            {"groups", groups.vectors.size()}}}};
    std::cout << out.dump(2) << "\n";
    return 0;
}
