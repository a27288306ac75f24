#pragma once
/// @file
/// Build-time model (seed 002 Section 2, Eq. 1-4; their text was lost in extraction and is
/// reconstructed here from the prose):
///   Eq. 1  T_total = T_mark + T_jump + T_delay            (vpsim adds recoat per layer)
///   Eq. 2  T_mark  = sum over mark vectors of length / mark speed (+ dwell of point marks): marks
///          run at constant speed, their start and stop being absorbed by the delays
///   Eq. 3  T_jump  = sum over the J jumps of t_acc + t_cns + t_dcc, per-axis trapezoidal or
///          triangular profiles under the machine limits, the slower axis deciding, each jump
///          starting with the last mark's velocity and ending at rest (plan/scanner.h)
///   Eq. 4  T_delay = n_j d_jump + n_m d_mark + n_p d_poly: a jump delay after every jump, a mark
///          delay after every mark followed by a jump (or ending the layer), a polygon delay
///          between two chained marks. Laser on/off delays do not add time (seed 002).
/// DLP layers take their masks' exposure time (highest pixel dose / projector irradiance: grey
/// levels dim pixels within one exposure) plus recoat. Units: s.

#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/plan/machine/scanner.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim {
class ConfigNode;
}

namespace vpsim::plan {

struct BuildTimeOptions {
    ScannerConfig scanner;
    double recoatTime = 0;           ///< s per layer (`machine.recoat_time`)
    double projectorIrradiance = 0;  ///< mW/mm^2 at the resin (DLP; `machine.projector_irradiance`)
    /// Replace a jump between two moving marks by seed 000's transition arcs when faster
    /// (no jump or mark delay then: the scanner never stops).
    bool transitionArcs = false;
};

/// The build-time options of a machine (its scanner, recoat time and projector irradiance).
BuildTimeOptions buildTimeOptions(const Machine& machine);
/// Reads a `machine` section (plan/machine/machine.h machineFromConfig: `scanner`, `recoat_time`,
/// `projector_irradiance`, all optional). @throw InputError naming the key
BuildTimeOptions buildTimeOptionsFromConfig(const ConfigNode& machine);

struct LayerTime {
    double mark = 0, jump = 0, delays = 0, recoat = 0, exposure = 0;  ///< s
    long long marks = 0, jumps = 0, arcs = 0;
    long long jumpDelays = 0, markDelays = 0, polygonDelays = 0;
    /// Marks whose axis speed exceeds process_speed: the planner asked for more than the
    /// scanner's process limits allow (the time still uses the planned speed).
    long long marksAboveProcessSpeed = 0;
    double total() const { return mark + jump + delays + recoat + exposure; }
};

struct BuildTime {
    std::vector<LayerTime> layers;
    LayerTime sum;  ///< all layers together
    double total() const { return sum.total(); }
    /// `build_time_s`: {total, mark, jump, delays, recoat, exposure, counts {...}, per_layer [...]}
    nlohmann::json toJson() const;
};

/// Time of one layer's moves (Eq. 1-4), without recoat.
LayerTime layerMoveTime(const std::vector<ScanMove>& moves, const BuildTimeOptions& options);

/// The whole plan: each layer's trajectory when it has one, else its vectors in plan order (with
/// jumps where they do not chain) and points dwelt in plan order; masks for DLP layers.
/// @throw InputError for mask layers without a positive projector irradiance
BuildTime estimateBuildTime(const ScanPlan& plan, const BuildTimeOptions& options);

}  // namespace vpsim::plan
