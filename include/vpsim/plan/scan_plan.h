#pragma once
/// @file
/// What the light source does on each layer: laser points and vectors (SLA) or a mask image
/// (DLP). The output of every planner and the input of the exposure engine; saved and loaded as
/// JSON. Units: mm, s, mW, mJ (dose mJ/mm^2).

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/geometry/layer_stack.h"
#include "vpsim/plan/machine/machine.h"

namespace vpsim::plan {

/// A laser dwell at one point: `energy` mJ delivered with the beam centred at (x, y).
struct LaserPoint {
    double x = 0, y = 0;  ///< mm
    double energy = 0;    ///< mJ (power x dwell time)
};

/// A laser vector scanned at constant speed (the build-time model adds accelerations and delays).
struct LaserVector {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< mm
    double power = 0;                       ///< mW
    double speed = 0;                       ///< mm/s; energy per length is power / speed (mJ/mm)
};

/// A projected greyscale mask: dose per pixel at the resin surface, row-major, row 0 at y =
/// originY.
struct MaskImage {
    int width = 0, height = 0;
    double originX = 0, originY = 0;  ///< mm, corner of pixel (0, 0)
    double pixelPitch = 0;            ///< mm
    std::vector<float> dose;          ///< mJ/mm^2 per pixel
};

/// One scanner move in execution order (plan/trajectory.h builds them): a mark (laser on) or a
/// jump (laser off). A jump's duration follows from the scanner kinematics (plan/scanner.h).
struct ScanMove {
    bool laserOn = false;
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< mm
    double power = 0;                       ///< mW (marks)
    double speed = 0;                       ///< mm/s (marks; 0 for jumps and dwells)
    double dwell = 0;                       ///< s at rest at (x1, y1) with the laser on
    int part = -1;                          ///< index of the layer part it belongs to
};

/// Everything exposed on one layer.
struct LayerPlan {
    double z = 0;  ///< mm, top surface of the layer (where the light enters)
    std::vector<LaserPoint> points;
    std::vector<LaserVector> vectors;
    std::vector<MaskImage> masks;
    /// The ordered scanner moves that execute `points` and `vectors` (empty until trajectories
    /// are built; saved as "trajectory" only when present).
    std::vector<ScanMove> trajectory;
};

/// A plan for a whole part, layers from the bottom (index 0) up.
struct ScanPlan {
    Machine machine;
    std::vector<LayerPlan> layers;
    /// Total energy delivered (mJ): points + vectors (power x length / speed) + masks.
    double totalEnergy() const;
};

nlohmann::json toJson(const ScanPlan& plan);
/// @throw InputError naming `file` and the key for malformed or impossible plans
ScanPlan scanPlanFromJson(const nlohmann::json& json, const std::string& file = "");
/// Saves as JSON (atomic write). @throw InputError when the file cannot be written
void saveScanPlan(const ScanPlan& plan, const std::string& path);
/// @throw InputError naming the file and the problem
ScanPlan loadScanPlan(const std::string& path);

/// The empty plan of `layers` (each layer's top z, nothing exposed) that planners fill.
ScanPlan emptyPlan(const geometry::LayerStack& layers, const Machine& machine);

}  // namespace vpsim::plan
