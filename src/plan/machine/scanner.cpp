#include "vpsim/plan/machine/scanner.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/config.h"

namespace vpsim::plan {
namespace {

double positiveOr(const ConfigNode& node, const std::string& key, Dimension dimension,
                  double fallback) {
    double value = node.quantity(key, dimension, fallback);
    if (!(value > 0) || !std::isfinite(value)) throw node.error(key, "must be positive");
    return value;
}

double delayOr(const ConfigNode& node, const std::string& key, double fallback) {
    double value = node.quantity(key, dim::TIME, fallback);
    if (!(value >= 0) || !std::isfinite(value)) throw node.error(key, "must not be negative");
    return value;
}

}  // namespace

ScannerConfig scannerFromConfig(const ConfigNode& section) {
    ScannerConfig config;
    config.machine.speed = positiveOr(section, "machine_speed", dim::SPEED, config.machine.speed);
    config.machine.acceleration =
        positiveOr(section, "machine_acceleration", dim::ACCELERATION, config.machine.acceleration);
    config.process.speed = positiveOr(section, "process_speed", dim::SPEED, config.process.speed);
    config.process.acceleration =
        positiveOr(section, "process_acceleration", dim::ACCELERATION, config.process.acceleration);
    if (config.process.speed > config.machine.speed)
        throw section.error("process_speed", "must not exceed machine_speed");
    if (config.process.acceleration > config.machine.acceleration)
        throw section.error("process_acceleration", "must not exceed machine_acceleration");
    if (section.has("delays")) {
        ConfigNode delays = section.child("delays");
        ScannerDelays& d = config.delays;
        d.laserOn = delayOr(delays, "laser_on", d.laserOn);
        d.laserOff = delayOr(delays, "laser_off", d.laserOff);
        d.jump = delayOr(delays, "jump", d.jump);
        d.mark = delayOr(delays, "mark", d.mark);
        d.polygon = delayOr(delays, "polygon", d.polygon);
    }
    return config;
}

double restToRestTime(double distance, const AxisLimits& limits) {
    const double d = std::abs(distance), a = limits.acceleration, v = limits.speed;
    if (d <= v * v / a) return 2.0 * std::sqrt(d / a);  // triangular: peak sqrt(a d) <= v
    return d / v + v / a;                               // trapezoidal: cruise at v
}

double axisMoveTime(double distance, double v0, const AxisLimits& limits) {
    const double a = limits.acceleration, vmax = limits.speed;
    double t = 0.0;
    if (std::abs(v0) > vmax) {  // brake to the limit first (only for inconsistent inputs)
        const double s = std::copysign((v0 * v0 - vmax * vmax) / (2.0 * a), v0);
        t += (std::abs(v0) - vmax) / a;
        distance -= s;
        v0 = std::copysign(vmax, v0);
    }
    if (v0 == 0.0) return t + restToRestTime(distance, limits);
    if (v0 < 0.0) distance = -distance, v0 = -v0;  // mirror so the axis moves towards +
    const double stop = v0 * v0 / (2.0 * a);
    if (distance >= stop) {
        // Keep going: accelerate from v0 to the peak, decelerate to rest at the target.
        // (vp^2 - v0^2)/2a + vp^2/2a = d  =>  vp = sqrt(a d + v0^2/2).
        const double vp = std::sqrt(a * distance + 0.5 * v0 * v0);
        if (vp <= vmax) return t + (vp - v0) / a + vp / a;
        const double cruise =
            distance - (vmax * vmax - v0 * v0) / (2.0 * a) - vmax * vmax / (2.0 * a);
        return t + (vmax - v0) / a + vmax / a + cruise / vmax;
    }
    // Overshoot (target closer than the braking distance) or reversal: brake to rest, then move
    // rest to rest back to the target (seed 002 Fig. 6, scenarios 1 and 3).
    return t + v0 / a + restToRestTime(distance - stop, limits);
}

namespace {

/// Accelerate (+a) from v0 to a peak, then brake (-a) to v1; +infinity when no such profile
/// covers `distance` (the peak would have to lie below v0 or v1).
double peakProfileTime(double distance, double v0, double v1, double vmax, double a) {
    // (vp^2 - v0^2)/2a + (vp^2 - v1^2)/2a = d  =>  vp^2 = a d + (v0^2 + v1^2)/2
    const double square = a * distance + 0.5 * (v0 * v0 + v1 * v1);
    if (square < 0) return INFINITY;
    const double root = std::sqrt(square), lowest = std::max(v0, v1) - 1e-9 * (1 + vmax);
    // Both signs of the peak may qualify (a negative peak: the axis keeps moving backwards,
    // slower for a while); the lower peak is the faster profile.
    if (-root >= lowest) return (-2.0 * root - v0 - v1) / a;
    const double vp = root;
    if (vp < lowest) return INFINITY;
    if (vp <= vmax) return std::max(0.0, (2.0 * vp - v0 - v1) / a);
    const double cruise = distance - (2.0 * vmax * vmax - v0 * v0 - v1 * v1) / (2.0 * a);
    return (2.0 * vmax - v0 - v1) / a + cruise / vmax;
}

}  // namespace

double axisMoveTime(double distance, double v0, double v1, const AxisLimits& limits) {
    const double a = limits.acceleration, vmax = limits.speed;
    double t = 0.0;
    if (std::abs(v0) > vmax) {  // brake to the limit first (only for inconsistent inputs)
        t += (std::abs(v0) - vmax) / a;
        distance -= std::copysign((v0 * v0 - vmax * vmax) / (2.0 * a), v0);
        v0 = std::copysign(vmax, v0);
    }
    if (std::abs(v1) > vmax) {  // and reach v1 from the limit at the end
        t += (std::abs(v1) - vmax) / a;
        distance -= std::copysign((v1 * v1 - vmax * vmax) / (2.0 * a), v1);
        v1 = std::copysign(vmax, v1);
    }
    // Mirroring (d, v0, v1) -> (-d, -v0, -v1) turns the brake-then-accelerate profile into the
    // peak profile.
    return t + std::min(peakProfileTime(distance, v0, v1, vmax, a),
                        peakProfileTime(-distance, -v0, -v1, vmax, a));
}

double jumpTime(const glm::dvec2& from, const glm::dvec2& to, const glm::dvec2& v0,
                const glm::dvec2& v1, const AxisLimits& limits) {
    return std::max(axisMoveTime(to.x - from.x, v0.x, v1.x, limits),
                    axisMoveTime(to.y - from.y, v0.y, v1.y, limits));
}

double jumpTime(const glm::dvec2& from, const glm::dvec2& to, const glm::dvec2& v0,
                const AxisLimits& limits) {
    return std::max(axisMoveTime(to.x - from.x, v0.x, limits),
                    axisMoveTime(to.y - from.y, v0.y, limits));
}

}  // namespace vpsim::plan
