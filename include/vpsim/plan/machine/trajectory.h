#pragma once
/// @file
/// Scan trajectories: a layer's points and vectors as the ordered mark and jump moves a scanner
/// runs (seed 002 Sections 2 and 4, seed 000 Section III-C). Vectors are grouped into layer parts
/// (by the sliced regions when given, otherwise by proximity); within a part, closed chains of
/// vectors (borders) are scanned first, starting at the border point closest to the first hatch
/// start (seed 002 Fig. 7: a dummy vertex is inserted there), then the hatches in the planner's
/// order (zig-zag or parallel, as planned). Points (DFBTP) become progressive row scans whose
/// speed is modulated so each point gets its energy, or stop-and-dwell moves. The parts are then
/// ordered by jump time (plan/part_order.h). Units: mm, s, mW.

#include <vector>

#include <glm/vec2.hpp>

#include "vpsim/geometry/polygons.h"
#include "vpsim/plan/machine/part_order.h"
#include "vpsim/plan/machine/scanner.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::plan {

/// How laser points are scanned.
enum class PointStrategy {
    /// rows scanned at one constant speed (process speed, or less where the power runs out),
    /// each point's cell at the power that gives it its energy
    Modulated,
    Dwell,  ///< jump to each point, stop, dwell energy/power with the laser on
};

struct TrajectoryOptions {
    ScannerConfig scanner;
    OrderMethod order = OrderMethod::Auto;
    PointStrategy points = PointStrategy::Modulated;
    double partGap = 0.2;  ///< mm: vectors closer than this belong to one part (no regions given)
    /// Let the ordering choose entry points: after the order is fixed, each part may be scanned
    /// backwards (its marks reversed, in reverse order) where that shortens the jumps, chosen
    /// exactly along the order by dynamic programming over the two directions. Off: seed 002's
    /// rule (enter at the contour point nearest the hatch start).
    bool chooseEntry = false;
};

/// One layer's moves and how its parts were ordered.
struct LayerTrajectory {
    std::vector<ScanMove> moves;
    int parts = 0;
    OrderResult order;      ///< over the parts; cost = jump time between parts (s)
    int reversedParts = 0;  ///< parts scanned backwards (TrajectoryOptions::chooseEntry)
};

/// Velocity (mm/s) at the end of a move: a moving mark's direction times its speed, else zero.
glm::dvec2 endVelocity(const ScanMove& move);
/// Velocity (mm/s) at the start of a move: the same as at its end, since marks run at constant
/// speed (the jump before it brings the scanner up to it).
glm::dvec2 startVelocity(const ScanMove& move);

/// Builds one layer. `region` (may be null) is the sliced layer; each of its outer contours with
/// holes is one part. `laserPower` (mW) is used for points.
/// @throw InputError from the ordering (exact with too many parts)
LayerTrajectory buildLayerTrajectory(const LayerPlan& layer, double laserPower,
                                     const TrajectoryOptions& options,
                                     const geometry::PolygonSet* region = nullptr);

/// Every layer; `regions` (may be null) holds one sliced region per layer.
/// @throw InputError when `regions` has a different layer count, or from buildLayerTrajectory
std::vector<LayerTrajectory> buildTrajectories(
    const ScanPlan& plan, const TrajectoryOptions& options,
    const std::vector<geometry::PolygonSet>* regions = nullptr);

/// Stores each layer's moves in plan.layers[i].trajectory (saved with the plan).
void attachTrajectories(ScanPlan& plan, const std::vector<LayerTrajectory>& trajectories);

}  // namespace vpsim::plan
