#pragma once
/// @file
/// The job keys of trajectories and what the report shows of them: `plan.order` and
/// `plan.direction` (common keys of the laser planners), `scan_order` for report.json, and a
/// picture of one layer's scan path.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/plan/machine/build_time.h"
#include "vpsim/plan/machine/scan_direction.h"
#include "vpsim/plan/machine/trajectory.h"

namespace vpsim {
class ConfigNode;
}

namespace vpsim::plan {

/// `scan_order` for report.json: {"layers": [{"layer", "parts", "method", "proven_optimal",
/// "jump_time_s", "nearest_neighbour_jump_time_s"}...], "jump_time_s", "nearest_neighbour_jump_
/// time_s", "layers_proven_optimal"} (jump times between parts, s). Layers without parts are
/// left out of the list.
nlohmann::json scanOrderJson(const std::vector<LayerTrajectory>& trajectories);

/// For plans with laser points, the build time of both point strategies (the modulated row scan
/// and stop-and-dwell, which decides whether point plans are practical): {"modulated_s",
/// "dwell_s"}; null when the plan has no points.
nlohmann::json pointStrategyJson(const ScanPlan& plan, const TrajectoryOptions& trajectory,
                                 const BuildTimeOptions& timing);

/// What the run reports about scanning a plan.
struct ScanSchedule {
    std::vector<LayerTrajectory> layers;  ///< empty for DLP plans
    nlohmann::json buildTime;             ///< `build_time_s` (BuildTime::toJson)
    nlohmann::json scanOrder;             ///< `scan_order` (null for DLP plans)
    nlohmann::json pointStrategies;       ///< pointStrategyJson (null without points)
    /// report.json's "laser" (laserUseJson: power and speed ranges against the limits); null for
    /// DLP plans. The pipeline fills it (it knows the machine's minimum power).
    nlohmann::json laser;
};

/// One call for the run: builds the trajectories of a laser plan and stores them in the plan
/// (`regions`, one per layer, may be null), then estimates the build time. A DLP plan without a
/// projector irradiance gets `build_time_s` with "exposure": null and a "note" instead of an error.
/// @throw InputError from the ordering or the build-time model
ScanSchedule scheduleScans(ScanPlan& plan, const TrajectoryOptions& trajectory,
                           const BuildTimeOptions& timing,
                           const std::vector<geometry::PolygonSet>* regions = nullptr);

/// The index of the layer with the most parts (the most telling picture), 0 when none has any.
size_t busiestLayer(const std::vector<LayerTrajectory>& trajectories);

/// Marks and jumps within a part drawn at most in a layer's scan-path figure (every k-th beyond).
constexpr size_t SCAN_PATH_SEGMENTS = 5000;

/// One layer's scan path as `stem`.svg and .png with mm axes at the true aspect ratio: marks
/// solid, jumps within a part dashed grey, jumps between parts dashed red, and the part order as
/// a line through the parts' first marks; a large layer draws every k-th mark and jump within a
/// part (SCAN_PATH_SEGMENTS of each) and says so under the plot.
/// @throw InputError when a file cannot be written
void writeScanPathFigure(const std::string& stem, const std::vector<ScanMove>& moves,
                         const std::string& title);

}  // namespace vpsim::plan
