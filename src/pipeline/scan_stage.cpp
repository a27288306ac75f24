// The scan stage of a run (stages.h): trajectories, part order and build time of the plan, and
// the picture that shows them (scan_path.svg).
#include "vpsim/pipeline/stages.h"

#include "vpsim/plan/machine/laser_limits.h"

namespace vpsim::pipeline {
namespace {

/// Whether every layer that exposes laser points or vectors already has its trajectory.
bool hasTrajectories(const plan::ScanPlan& plan) {
    bool any = false;
    for (const auto& layer : plan.layers) {
        const bool laser = !layer.vectors.empty() || !layer.points.empty();
        if (laser && layer.trajectory.empty()) return false;
        any = any || laser;
    }
    return any;
}

}  // namespace

plan::ScanSchedule scanStage(const Job& job, const geometry::LayerStack& layers,
                             plan::ScanPlan& plan) {
    const plan::BuildTimeOptions timing = plan::buildTimeOptions(job.machine);
    const nlohmann::json laser =
        plan::laserUseJson(plan, job.machine.laserPowerMin, job.machine.scanner.process.speed);
    if (hasTrajectories(plan)) {  // a saved plan keeps its own order
        plan::ScanSchedule schedule;
        schedule.buildTime = plan::estimateBuildTime(plan, timing).toJson();
        schedule.laser = laser;
        return schedule;
    }
    plan::TrajectoryOptions options;
    options.scanner = timing.scanner;
    options.order = job.scanOrder;
    std::vector<geometry::PolygonSet> regions;
    for (const auto& layer : layers.layers) regions.push_back(layer.region);
    const bool sameLayers = regions.size() == plan.layers.size();
    plan::ScanSchedule schedule =
        plan::scheduleScans(plan, options, timing, sameLayers ? &regions : nullptr);
    schedule.laser = laser;
    return schedule;
}

void addScheduleFigures(const plan::ScanSchedule& schedule, nlohmann::json& planner) {
    planner["build_time_s"] = schedule.buildTime;
    if (!schedule.scanOrder.is_null()) planner["scan_order"] = schedule.scanOrder;
    if (!schedule.pointStrategies.is_null())
        planner["point_build_time_s"] = schedule.pointStrategies;
    if (!schedule.laser.is_null()) {  // the planner's fit (if any) and the plan's ranges
        nlohmann::json& laser = planner["laser"];
        if (!laser.is_object()) laser = nlohmann::json::object();
        laser.update(schedule.laser);
    }
}

void writeScanFiles(const plan::ScanSchedule& schedule, const plan::ScanPlan& plan,
                    const std::string& outDir, bool figures) {
    // scan.cli is written by the job's exporters (exportStage), like every machine file.
    if (figures && !schedule.layers.empty()) {
        const size_t k = plan::busiestLayer(schedule.layers);
        plan::writeScanPathFigure(outDir + "/scan_path", schedule.layers[k].moves,
                                  "scan path of layer " + std::to_string(k) + " (" +
                                      std::to_string(schedule.layers[k].parts) + " parts, " +
                                      schedule.layers[k].order.method + " order)");
    }
}

}  // namespace vpsim::pipeline
