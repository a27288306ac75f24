#pragma once
/// @file
/// Transition trajectories between two moving states (seed 000 Section III-C1, Fig. 24-26): an
/// arc tangent to the start velocity at A, a straight segment BC tangent to both arcs on which the
/// speed changes from |vA| to |vE|, and an arc tangent to the end velocity at E. Both arcs have
/// the radius R = 3 vmax^2 / amax (three times the smallest radius the acceleration limit allows)
/// and are run at constant speed, so their centripetal acceleration v^2/R stays at most amax/3.
/// Each end has two circles (left and right of its velocity), giving four candidates; the fastest
/// is kept. Units: mm, s.

#include <array>

#include <glm/vec2.hpp>

#include "vpsim/plan/machine/scanner.h"

namespace vpsim::plan {

/// One candidate transition A -> B (arc 1) -> C (segment) -> E (arc 2).
struct ArcTransition {
    bool feasible = false;     ///< false: the circles overlap for a cross tangent, or BC is too
                               ///< short to change the speed at `limits.acceleration`
    int turn1 = 0, turn2 = 0;  ///< +1 counter-clockwise, -1 clockwise
    double radius = 0;         ///< mm
    glm::dvec2 centre1{}, centre2{};
    glm::dvec2 a{}, b{}, c{}, e{};                             ///< mm
    double arc1Length = 0, segmentLength = 0, arc2Length = 0;  ///< mm
    double time = 0;                                           ///< s (infinite when not feasible)
};

/// R = 3 v^2 / a (mm).
double transitionRadius(const AxisLimits& limits);

/// The four candidates (turns (+,+), (+,-), (-,+), (-,-)).
/// @throw InputError when a speed is zero or above limits.speed
std::array<ArcTransition, 4> arcCandidates(const glm::dvec2& a, const glm::dvec2& va,
                                           const glm::dvec2& e, const glm::dvec2& ve,
                                           const AxisLimits& limits);

/// The fastest feasible candidate (feasible = false when none is).
ArcTransition fastestArcTransition(const glm::dvec2& a, const glm::dvec2& va, const glm::dvec2& e,
                                   const glm::dvec2& ve, const AxisLimits& limits);

/// Minimal time (s) to cover `length` mm on a line starting at speed v0 and ending at v1 with
/// |a| <= acceleration, |v| <= vmax; infinite when the length cannot change the speed.
double segmentTime(double length, double v0, double v1, const AxisLimits& limits);

}  // namespace vpsim::plan
