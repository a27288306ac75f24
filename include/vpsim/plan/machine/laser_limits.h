#pragma once
/// @file
/// A laser plan the machine can run (issue 23 item 1). The laser's power lies in
/// [machine.laser_power_min, machine.laser_power] and a mark's axis speed is at most the
/// scanner's process speed; marks run at constant speed (the scanner accelerates in the jumps,
/// plan/machine/scanner.h), so the dose per length P/v holds along each mark. A planner states
/// its dose as energy per length (vectors) or energy (points) and fitPlanToLimits() turns that
/// into powers and speeds within the limits:
/// - a chain of collinear vectors that continue one another (a hatch line cut into pieces, a row
///   of dots) runs at one speed, and each piece's power gives it its energy at that speed: the
///   process limit along its direction, or slower where the laser's full power cannot give its
///   densest piece its energy at it (and no faster than its scan path's speed, below); a chain
///   spanning more than the power range is cut into runs that each fit it;
/// - a scan path (vectors in plan order that chain, or continue one scan line after a gap) that
///   ends in a stop runs no faster than sqrt(a L / 2), a the jumps' acceleration and L the
///   path's length: the speed that minimises its mark time L / v plus the 2 v / a of braking and
///   re-accelerating at its end (a dense field of short lines spends its time in reversals
///   otherwise), and no slower than its weakest piece's energy at the minimum power allows;
/// - rows of dots on a grid (the inverse planner, DFBTP's corners) become such chains, one
///   segment of one pitch per dot (dose modulated along vectors by power), along x or y,
///   whichever gives fewer chains. An isolated dot stays a dwell at the laser's power (dose by
///   dwell time);
/// - a vector or dot whose own peak dose is below `negligibleDose` is dropped (not scanned at
///   kilometres per second), except inside a chain, where it keeps its small power so that the
///   scan line goes on without a jump; one whose power would fall below the minimum is raised to it
///   when it needs at least half of it, and dropped otherwise.
/// checkDoseReachable() refuses a job whose target dose cannot be delivered within the limits
/// before anything is planned. Units: mm, s, mW, mJ (dose mJ/mm^2).

#include <nlohmann/json_fwd.hpp>

#include "vpsim/plan/scan_plan.h"

namespace vpsim::plan {

/// What a laser plan must respect and what it may drop.
struct LaserLimits {
    double powerMin = 0;        ///< mW, `machine.laser_power_min`
    double powerMax = 10;       ///< mW, `machine.laser_power`
    double processSpeed = 300;  ///< mm/s per axis, `machine.scanner.process_speed`
    double beamRadius = 0.05;   ///< mm (We3D), for the peak dose of one vector or dot
    /// mJ/mm^2 of delivered dose: a vector or dot whose own peak (sqrt(2/pi) (P/v)/W for a line,
    /// 2 E/(pi W^2) for a dot) stays below it is dropped; 0 drops nothing.
    double negligibleDose = 0;
    /// mm/s^2 per axis of the jumps (`machine.scanner.machine_acceleration`), for the speed of a
    /// scan path (see the file comment); 0 runs every mark as fast as the limits allow.
    double jumpAcceleration = 0;
    /// s: the delays a jump inside a line costs (jump and mark delays). A stretch of a run that
    /// needs less than half the minimum power is marked at the minimum power when that takes
    /// less than this, instead of being dropped and jumped over; 0 always drops it.
    double gapDelay = 0;
};

/// The limits of `machine` (its jump acceleration included) for a beam of radius `beamRadius`
/// (mm); `negligibleDose` as above.
LaserLimits laserLimits(const Machine& machine, double beamRadius, double negligibleDose);

/// Largest path speed (mm/s) of a mark from (x0, y0) to (x1, y1) whose axis speeds stay within
/// `processSpeed`: processSpeed * length / max(|dx|, |dy|) (processSpeed for a point).
double markSpeedLimit(double x0, double y0, double x1, double y1, double processSpeed);

/// What fitPlanToLimits() did.
struct LimitFit {
    long long droppedNegligible = 0;     ///< vectors and dots below the negligible dose
    long long droppedBelowMinPower = 0;  ///< vectors needing less than half the minimum power
    long long raisedToMinPower = 0;      ///< vectors run at the minimum power (more dose)
    long long pointsAsVectors = 0;       ///< dots turned into segments of a chain
    long long dwellPoints = 0;           ///< isolated dots kept as dwells
    /// {"dropped_negligible", "dropped_below_min_power", "raised_to_min_power",
    /// "points_as_vectors", "dwell_points"}
    nlohmann::json toJson() const;
};

/// Fits every layer's vectors and points to `limits` (see the file comment). `dotPitch` (mm) is
/// the pitch of the planner's dot grid: dots a pitch apart along x (or y, whichever gives fewer
/// chains) form a chain; 0 keeps every dot as a dwell. Keeps each vector's energy per length
/// except where it is raised to the minimum power or dropped.
LimitFit fitPlanToLimits(ScanPlan& plan, const LaserLimits& limits, double dotPitch = 0);

/// A laser plan's use of the machine for report.json: {"power_mW": [min, max], "speed_mm_per_s":
/// [min, max], "power_limits_mW": [min, max], "process_speed_mm_per_s",
/// "marks_above_process_speed", "marks_below_min_power", "marks_above_max_power"} over its
/// marks (dwells at the laser's power); null for a plan without laser marks.
nlohmann::json laserUseJson(const ScanPlan& plan, double powerMin, double processSpeed);

/// Refuses, before planning, a target dose `targetDose` (mJ/mm^2 delivered) that a field of lines
/// `lineSpacing` (mm) apart cannot get within the limits: at the minimum power and the process
/// speed it would already be more than the target. (Any larger dose is reachable by scanning
/// slower.) @throw InputError in one line saying what to change
void checkDoseReachable(const Machine& machine, double targetDose, double lineSpacing);

}  // namespace vpsim::plan
