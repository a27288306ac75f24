#include "vpsim/plan/machine/transition_arc.h"

#include <cmath>
#include <limits>

#include "vpsim/core/error.h"

namespace vpsim::plan {
namespace {

glm::dvec2 perp(const glm::dvec2& v) {
    return {-v.y, v.x};
}

glm::dvec2 rotate(const glm::dvec2& v, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * v.x - s * v.y, s * v.x + c * v.y};
}

/// Angle swept from p to q around `centre` turning the way `turn` says, in [0, 2 pi).
double sweep(const glm::dvec2& centre, const glm::dvec2& p, const glm::dvec2& q, int turn) {
    double delta =
        std::atan2(q.y - centre.y, q.x - centre.x) - std::atan2(p.y - centre.y, p.x - centre.x);
    delta *= turn;
    delta = std::fmod(delta, 2.0 * M_PI);
    if (delta < 0) delta += 2.0 * M_PI;
    if (delta > 2.0 * M_PI - 1e-12) delta = 0.0;  // round-off of a full turn
    return delta;
}

ArcTransition candidate(const glm::dvec2& a, const glm::dvec2& ua, double speedA,
                        const glm::dvec2& e, const glm::dvec2& ue, double speedE, int turn1,
                        int turn2, const AxisLimits& limits) {
    ArcTransition t;
    t.turn1 = turn1, t.turn2 = turn2;
    t.radius = transitionRadius(limits);
    t.a = a, t.e = e;
    const double r = t.radius;
    // A point P on a circle around C turning `s` moves along u when P = C - s R perp(u).
    t.centre1 = a + double(turn1) * r * perp(ua);
    t.centre2 = e + double(turn2) * r * perp(ue);
    const glm::dvec2 d = t.centre2 - t.centre1;
    const double dist = std::hypot(d.x, d.y);
    glm::dvec2 u;
    if (turn1 == turn2) {  // outer tangent: parallel to the line of centres
        if (dist < 1e-12) {
            u = ua;  // same circle: the segment degenerates to a point
        } else {
            u = d / dist;
        }
        t.segmentLength = dist;
    } else {  // cross tangent: C - B = L u - 2 s1 R perp(u) = d
        if (dist < 2.0 * r) {
            t.time = std::numeric_limits<double>::infinity();
            return t;
        }
        t.segmentLength = std::sqrt(dist * dist - 4.0 * r * r);
        const double phi = std::atan2(-2.0 * turn1 * r, t.segmentLength);
        u = rotate(d / dist, -phi);
    }
    t.b = t.centre1 - double(turn1) * r * perp(u);
    t.c = t.centre2 - double(turn2) * r * perp(u);
    t.arc1Length = r * sweep(t.centre1, a, t.b, turn1);
    t.arc2Length = r * sweep(t.centre2, t.c, e, turn2);
    const double middle = segmentTime(t.segmentLength, speedA, speedE, limits);
    t.feasible = std::isfinite(middle);
    t.time = t.feasible ? t.arc1Length / speedA + middle + t.arc2Length / speedE
                        : std::numeric_limits<double>::infinity();
    return t;
}

}  // namespace

double transitionRadius(const AxisLimits& limits) {
    return 3.0 * limits.speed * limits.speed / limits.acceleration;
}

double segmentTime(double length, double v0, double v1, const AxisLimits& limits) {
    const double a = limits.acceleration, vmax = limits.speed;
    if (std::abs(v1 * v1 - v0 * v0) / (2.0 * a) > length + 1e-12)
        return std::numeric_limits<double>::infinity();
    // Accelerate to the peak, then decelerate to v1: (vp^2-v0^2)/2a + (vp^2-v1^2)/2a = L.
    const double vp = std::sqrt(a * length + 0.5 * (v0 * v0 + v1 * v1));
    if (vp <= vmax) return (2.0 * vp - v0 - v1) / a;
    const double cruise =
        length - (vmax * vmax - v0 * v0) / (2.0 * a) - (vmax * vmax - v1 * v1) / (2.0 * a);
    return (2.0 * vmax - v0 - v1) / a + cruise / vmax;
}

std::array<ArcTransition, 4> arcCandidates(const glm::dvec2& a, const glm::dvec2& va,
                                           const glm::dvec2& e, const glm::dvec2& ve,
                                           const AxisLimits& limits) {
    const double sa = std::hypot(va.x, va.y), se = std::hypot(ve.x, ve.y);
    if (!(sa > 0) || !(se > 0))
        throw InputError("a transition arc needs moving start and end states");
    if (sa > limits.speed * (1 + 1e-12) || se > limits.speed * (1 + 1e-12))
        throw InputError("transition speeds exceed the speed limit");
    const glm::dvec2 ua = va / sa, ue = ve / se;
    return {candidate(a, ua, sa, e, ue, se, +1, +1, limits),
            candidate(a, ua, sa, e, ue, se, +1, -1, limits),
            candidate(a, ua, sa, e, ue, se, -1, +1, limits),
            candidate(a, ua, sa, e, ue, se, -1, -1, limits)};
}

ArcTransition fastestArcTransition(const glm::dvec2& a, const glm::dvec2& va, const glm::dvec2& e,
                                   const glm::dvec2& ve, const AxisLimits& limits) {
    std::array<ArcTransition, 4> all = arcCandidates(a, va, e, ve, limits);
    ArcTransition best = all[0];
    for (const ArcTransition& t : all)
        if (t.time < best.time) best = t;
    return best;
}

}  // namespace vpsim::plan
