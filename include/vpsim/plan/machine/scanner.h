#pragma once
/// @file
/// Galvanometer scanner kinematics and delays (seed 002 Section 2 and Section 4, Table 1).
/// Each mirror axis moves with its own trapezoidal (or triangular) velocity profile under
/// per-axis limits; a move takes as long as its slower axis. Marks (laser on) run at constant
/// speed, at most the process speed, so the dose P/v holds along the whole mark; every change of
/// speed happens with the laser off, in the jumps, under the machine limits: a jump starts with
/// the velocity the last mark had (seed 002's jumps) and ends with the velocity the next mark
/// starts with (the run-up of skywriting), or at rest before a dwell or at the end of a layer.
/// Units: mm, s.

#include <glm/vec2.hpp>

namespace vpsim {
class ConfigNode;
}

namespace vpsim::plan {

/// The five delays of seed 002 Table 1 (s). Laser on/off delays shift the laser switching
/// against the motion and do not add to the build time (seed 002 Section 2); they are kept so
/// exporters can pass them on.
struct ScannerDelays {
    double laserOn = 100e-6;
    double laserOff = 100e-6;
    double jump = 250e-6;    ///< after a jump vector
    double mark = 100e-6;    ///< between a mark vector and a jump vector
    double polygon = 50e-6;  ///< between two mark vectors
};

/// Per-axis limits of one kind of motion.
struct AxisLimits {
    double speed = 0;         ///< mm/s, per axis
    double acceleration = 0;  ///< mm/s^2, per axis
};

/// `machine.scanner`: seed 002's simulation values by default (2 m/s, 20 m/s^2 machine; 0.3 m/s,
/// 2 m/s^2 process) and Table 1's typical delays.
struct ScannerConfig {
    AxisLimits machine{2000.0, 20000.0};  ///< jumps
    AxisLimits process{300.0, 2000.0};    ///< marks
    ScannerDelays delays;
};

/// Parses a `machine.scanner` section: `machine_speed`, `machine_acceleration`, `process_speed`,
/// `process_acceleration` (quantities, e.g. "2 m/s", "20 m/s^2") and `delays` {`laser_on`,
/// `laser_off`, `jump`, `mark`, `polygon`} (times, e.g. "250 us"); every key is optional.
/// @throw InputError naming the key for a non-positive limit, a negative delay, process limits
/// above the machine's, or a value of the wrong dimension
ScannerConfig scannerFromConfig(const ConfigNode& section);

/// Time (s) for one axis to travel the signed displacement `distance` (mm), starting with the
/// signed velocity `v0` (mm/s) and ending at rest, with |v| <= limits.speed and
/// |a| <= limits.acceleration. Closed forms: a triangular or trapezoidal profile when the axis
/// can keep going the way it moves; otherwise it first brakes to rest (overshooting or
/// reversing, seed 002 Fig. 6 scenarios 1 and 3) and then moves rest to rest.
/// A |v0| above limits.speed is first braked to limits.speed.
double axisMoveTime(double distance, double v0, const AxisLimits& limits);

/// Time (s) for one axis to travel the signed displacement `distance` (mm) from the signed
/// velocity `v0` to the signed velocity `v1` (mm/s), |v| <= limits.speed, |a| <=
/// limits.acceleration: the faster of the two bang-bang profiles (accelerate then brake, or
/// brake then accelerate), each with a cruise at the speed limit when it would exceed it. Both
/// |v0| and |v1| above limits.speed are first brought to it (only for inconsistent inputs).
/// v1 = 0 is axisMoveTime(distance, v0, limits).
double axisMoveTime(double distance, double v0, double v1, const AxisLimits& limits);

/// Jump time (s) from `from` to `to` (mm) starting with velocity `v0` (mm/s) and ending at rest:
/// the slower of the two axes, each with the machine limits.
double jumpTime(const glm::dvec2& from, const glm::dvec2& to, const glm::dvec2& v0,
                const AxisLimits& limits);
/// Jump time (s) from `from` to `to` (mm), starting with velocity `v0` and ending with `v1`
/// (mm/s): the slower of the two axes, each with the machine limits.
double jumpTime(const glm::dvec2& from, const glm::dvec2& to, const glm::dvec2& v0,
                const glm::dvec2& v1, const AxisLimits& limits);

/// Time (s) for one axis to move `distance` mm from rest to rest: 2 sqrt(d/a) (triangular) up to
/// d = v^2/a, d/v + v/a (trapezoidal) beyond.
double restToRestTime(double distance, const AxisLimits& limits);

}  // namespace vpsim::plan
