// Seed 000's transition arcs (Fig. 24-26): tangent at every junction, radius 3 v^2/a, centripetal
// acceleration within the limit, four candidates with the fastest kept.
#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/plan/machine/transition_arc.h"

using namespace vpsim;
using namespace vpsim::plan;

namespace {

glm::dvec2 unit(const glm::dvec2& v) {
    return v / std::hypot(v.x, v.y);
}
double len(const glm::dvec2& v) {
    return std::hypot(v.x, v.y);
}

/// Direction of travel at p on a circle around c turning `turn`.
glm::dvec2 circleTangent(const glm::dvec2& c, const glm::dvec2& p, int turn) {
    glm::dvec2 r = unit(p - c);
    return double(turn) * glm::dvec2{-r.y, r.x};
}

}  // namespace

TEST_CASE("transition arcs are tangent, within limits, fastest of four", "[plan]") {
    const AxisLimits limits{300.0, 2000.0};  // R = 3 * 300^2 / 2000 = 135 mm
    CHECK(transitionRadius(limits) == Approx(135.0));
    const glm::dvec2 a{0, 0}, e{400, 150};
    const glm::dvec2 va{200, 0}, ve{0, 250};
    auto all = arcCandidates(a, va, e, ve, limits);
    int feasible = 0;
    double fastest = INFINITY;
    for (const ArcTransition& t : all) {
        if (!t.feasible) continue;
        ++feasible;
        fastest = std::min(fastest, t.time);
        const double r = t.radius;
        CHECK(len(t.a - t.centre1) == Approx(r));
        CHECK(len(t.b - t.centre1) == Approx(r));
        CHECK(len(t.c - t.centre2) == Approx(r));
        CHECK(len(t.e - t.centre2) == Approx(r));
        // Tangent to the start and end velocities, and BC tangent to both arcs.
        CHECK(len(circleTangent(t.centre1, t.a, t.turn1) - unit(va)) == Approx(0).margin(1e-9));
        CHECK(len(circleTangent(t.centre2, t.e, t.turn2) - unit(ve)) == Approx(0).margin(1e-9));
        if (t.segmentLength > 1e-9) {
            const glm::dvec2 u = unit(t.c - t.b);
            CHECK(len(circleTangent(t.centre1, t.b, t.turn1) - u) == Approx(0).margin(1e-9));
            CHECK(len(circleTangent(t.centre2, t.c, t.turn2) - u) == Approx(0).margin(1e-9));
            CHECK(len(t.c - t.b) == Approx(t.segmentLength));
        }
        // Constant speed on the arcs: centripetal acceleration v^2/R <= amax/3.
        CHECK(len(va) * len(va) / r <= limits.acceleration / 3 + 1e-9);
        CHECK(len(ve) * len(ve) / r <= limits.acceleration / 3 + 1e-9);
        // Time = arcs at their speeds + the fastest speed change along BC.
        CHECK(t.time == Approx(t.arc1Length / len(va) +
                               segmentTime(t.segmentLength, len(va), len(ve), limits) +
                               t.arc2Length / len(ve)));
    }
    CHECK(feasible >= 1);
    CHECK(fastestArcTransition(a, va, e, ve, limits).time == Approx(fastest));
}

TEST_CASE("straight-ahead transitions need no turning", "[plan]") {
    const AxisLimits limits{300.0, 2000.0};
    // Same line, same direction, same speed: both arcs of zero sweep, BC the whole way.
    ArcTransition t = fastestArcTransition({0, 0}, {100, 0}, {5, 0}, {100, 0}, limits);
    REQUIRE(t.feasible);
    CHECK(t.arc1Length == Approx(0).margin(1e-9));
    CHECK(t.arc2Length == Approx(0).margin(1e-9));
    CHECK(t.time == Approx(segmentTime(5, 100, 100, limits)));
    // The segment alone: accelerate from 100 to the peak and back over 5 mm (peak 141 mm/s < 300).
    const double vp = std::sqrt(2000.0 * 5 + 100.0 * 100);
    CHECK(segmentTime(5, 100, 100, limits) == Approx(2 * (vp - 100) / 2000.0));
    CHECK_THROWS_AS(arcCandidates({0, 0}, {0, 0}, {1, 0}, {1, 0}, limits), InputError);
}
