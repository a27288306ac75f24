#include "vpsim/plan/machine/scan_report.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/image.h"

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

void writeScanPathSvg(const std::string& path, const std::vector<ScanMove>& moves,
                      const std::string& title) {
    PlotSeries marks{"marks", {}, {}, "#1f77b4", false};
    PlotSeries inner{"jumps in a part", {}, {}, "#999999", true};
    PlotSeries between{"jumps between parts", {}, {}, "#d62728", true};
    PlotSeries order{"part order", {}, {}, "#ff7f0e", false};
    auto add = [](PlotSeries& s, const ScanMove& m) {
        s.x.insert(s.x.end(), {m.x0, m.x1, NAN});
        s.y.insert(s.y.end(), {m.y0, m.y1, NAN});
    };
    int part = -2;
    for (size_t i = 0; i < moves.size(); ++i) {
        const ScanMove& m = moves[i];
        if (m.laserOn) {
            add(marks, m);
            if (m.part != part) order.x.push_back(m.x0), order.y.push_back(m.y0), part = m.part;
        } else {
            const bool crosses =
                i + 1 < moves.size() && i > 0 && moves[i + 1].part != moves[i - 1].part;
            add(crosses ? between : inner, m);
        }
    }
    writeSvgLinePlot(path, title, "x (mm)", "y (mm)", {marks, inner, between, order});
}

}  // namespace vpsim::plan
