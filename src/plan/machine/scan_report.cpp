#include "vpsim/plan/machine/scan_report.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/plot/plot.h"

namespace vpsim::plan {

nlohmann::json scanOrderJson(const std::vector<LayerTrajectory>& trajectories) {
    nlohmann::json layers = nlohmann::json::array();
    double jump = 0, nn = 0;
    size_t proven = 0, counted = 0;
    for (size_t i = 0; i < trajectories.size(); ++i) {
        const LayerTrajectory& t = trajectories[i];
        if (t.parts == 0) continue;
        ++counted;
        proven += t.order.provenOptimal;
        jump += t.order.cost, nn += t.order.nearestNeighbourCost;
        layers.push_back({{"layer", i},
                          {"parts", t.parts},
                          {"method", t.order.method},
                          {"proven_optimal", t.order.provenOptimal},
                          {"jump_time_s", t.order.cost},
                          {"nearest_neighbour_jump_time_s", t.order.nearestNeighbourCost}});
    }
    return {{"layers", layers},
            {"jump_time_s", jump},
            {"nearest_neighbour_jump_time_s", nn},
            {"layers_with_parts", counted},
            {"layers_proven_optimal", proven}};
}

nlohmann::json pointStrategyJson(const ScanPlan& plan, const TrajectoryOptions& trajectory,
                                 const BuildTimeOptions& timing) {
    bool points = false;
    for (const auto& layer : plan.layers) points = points || !layer.points.empty();
    if (!points) return nullptr;
    nlohmann::json out;
    for (PointStrategy strategy : {PointStrategy::Modulated, PointStrategy::Dwell}) {
        TrajectoryOptions options = trajectory;
        options.points = strategy;
        ScanPlan copy = plan;
        auto layers = buildTrajectories(copy, options);
        attachTrajectories(copy, layers);
        const bool modulated = strategy == PointStrategy::Modulated;
        out[modulated ? "modulated_s" : "dwell_s"] = estimateBuildTime(copy, timing).total();
    }
    return out;
}

ScanSchedule scheduleScans(ScanPlan& plan, const TrajectoryOptions& trajectory,
                           const BuildTimeOptions& timing,
                           const std::vector<geometry::PolygonSet>* regions) {
    ScanSchedule out;
    bool masks = false, laser = false;
    for (const auto& layer : plan.layers) {
        masks = masks || !layer.masks.empty();
        laser = laser || !layer.vectors.empty() || !layer.points.empty();
    }
    if (laser) {
        out.layers = buildTrajectories(plan, trajectory, regions);
        attachTrajectories(plan, out.layers);
        out.scanOrder = scanOrderJson(out.layers);
        out.pointStrategies = pointStrategyJson(plan, trajectory, timing);
    }
    if (masks && !(timing.projectorIrradiance > 0)) {
        BuildTimeOptions recoatOnly = timing;
        ScanPlan withoutMasks = plan;
        for (auto& layer : withoutMasks.layers) layer.masks.clear();
        out.buildTime = estimateBuildTime(withoutMasks, recoatOnly).toJson();
        out.buildTime["exposure"] = nullptr;
        out.buildTime["total"] = nullptr;
        out.buildTime["note"] =
            "machine.projector_irradiance not given: mask exposure time unknown";
        return out;
    }
    out.buildTime = estimateBuildTime(plan, timing).toJson();
    return out;
}

size_t busiestLayer(const std::vector<LayerTrajectory>& trajectories) {
    size_t best = 0;
    for (size_t i = 0; i < trajectories.size(); ++i)
        if (trajectories[i].parts > trajectories[best].parts) best = i;
    return best;
}

void writeScanPathFigure(const std::string& stem, const std::vector<ScanMove>& moves,
                         const std::string& title) {
    plot::Curve marks{"marks", {}, {}, {31, 119, 180}, false};
    plot::Curve inner{"jumps in a part", {}, {}, {153, 153, 153}, true};
    plot::Curve between{"jumps between parts", {}, {}, {214, 39, 40}, true};
    plot::Curve order{"part order", {}, {}, {255, 127, 14}, false};
    size_t markCount = 0, innerCount = 0;
    for (size_t i = 0; i < moves.size(); ++i)
        if (moves[i].laserOn)
            ++markCount;
        else
            innerCount +=
                !(i + 1 < moves.size() && i > 0 && moves[i + 1].part != moves[i - 1].part);
    // A large layer draws every k-th mark and jump within a part (the hatch at a k times wider
    // spacing), so the figure stays readable and a few MB at most; jumps between parts and the
    // order are all drawn.
    const size_t markStep = (markCount + SCAN_PATH_SEGMENTS - 1) / SCAN_PATH_SEGMENTS;
    const size_t innerStep = (innerCount + SCAN_PATH_SEGMENTS - 1) / SCAN_PATH_SEGMENTS;
    auto add = [](plot::Curve& c, const ScanMove& m) {
        c.x.insert(c.x.end(), {m.x0, m.x1, NAN});
        c.y.insert(c.y.end(), {m.y0, m.y1, NAN});
    };
    int part = -2;
    size_t markIndex = 0, innerIndex = 0;
    for (size_t i = 0; i < moves.size(); ++i) {
        const ScanMove& m = moves[i];
        if (m.laserOn) {
            if (markIndex++ % std::max<size_t>(1, markStep) == 0) add(marks, m);
            if (m.part != part) order.x.push_back(m.x0), order.y.push_back(m.y0), part = m.part;
        } else if (i + 1 < moves.size() && i > 0 && moves[i + 1].part != moves[i - 1].part) {
            add(between, m);
        } else if (innerIndex++ % std::max<size_t>(1, innerStep) == 0) {
            add(inner, m);
        }
    }
    plot::LineFigure f;
    f.title = title;
    f.xLabel = "x (mm)";
    f.yLabel = "y (mm)";
    f.equalAspect = true;
    f.curves = {marks, inner, between, order};
    if (markStep > 1 || innerStep > 1)
        f.note = "drawn: 1 in " + std::to_string(std::max<size_t>(1, markStep)) + " of the " +
                 std::to_string(markCount) + " marks, 1 in " +
                 std::to_string(std::max<size_t>(1, innerStep)) + " of the " +
                 std::to_string(innerCount) + " jumps in a part";
    plot::writeLineFigure(stem, f);
}

}  // namespace vpsim::plan
