#include "vpsim/plan/machine/scan_direction.h"

#include <cmath>
#include <cstdio>

#include "vpsim/core/error.h"
#include "vpsim/core/units.h"
#include "vpsim/plan/aces/aces.h"

namespace vpsim::plan {
namespace {

double wrapHalfTurn(double angle) {
    double a = std::fmod(angle, M_PI);
    if (a < 0) a += M_PI;
    return a >= M_PI ? 0.0 : a;
}

}  // namespace

DirectionRule parseDirectionRule(const std::string& text, const std::string& key,
                                 const std::string& file) {
    DirectionRule rule;
    if (text == "min-edge-projection") return rule;
    if (text == "longest-edge") {
        rule.kind = DirectionRule::Kind::LongestEdge;
        return rule;
    }
    try {
        rule.angle = wrapHalfTurn(parseQuantity(text, dim::ANGLE, key, file));
    } catch (const InputError&) {
        throw InputError("'" + text +
                             "' is not a scan direction (min-edge-projection, longest-edge or an "
                             "angle such as \"30 deg\")",
                         file, key);
    }
    rule.kind = DirectionRule::Kind::Fixed;
    return rule;
}

std::string toString(const DirectionRule& rule) {
    switch (rule.kind) {
        case DirectionRule::Kind::MinEdgeProjection: return "min-edge-projection";
        case DirectionRule::Kind::LongestEdge: return "longest-edge";
        case DirectionRule::Kind::Fixed: break;
    }
    char text[32];
    std::snprintf(text, sizeof text, "%.6g deg", rule.angle * 180.0 / M_PI);
    return text;
}

double edgeProjectionSum(const geometry::PolygonSet& region, double direction) {
    const glm::dvec2 d{std::cos(direction), std::sin(direction)};
    double sum = 0;
    for (const auto& contour : region.contours())
        for (size_t i = 0; i < contour.size(); ++i) {
            const glm::dvec2 e = contour[(i + 1) % contour.size()] - contour[i];
            sum += std::abs(e.x * d.y - e.y * d.x);
        }
    return sum;
}

double scanDirection(const geometry::PolygonSet& region, const DirectionRule& rule) {
    if (rule.kind == DirectionRule::Kind::Fixed) return rule.angle;
    if (region.empty()) return 0.0;
    if (rule.kind == DirectionRule::Kind::LongestEdge) return longestEdgeDirection(region);
    // Seed 002's algorithm: (1) list the edge orientations, (2) the projection sum for each,
    // (3) keep the minimum. Ties go to the first (longest-edge order is not needed: equal sums
    // give equal vector counts).
    double best = 0.0, bestSum = INFINITY;
    for (const auto& contour : region.contours())
        for (size_t i = 0; i < contour.size(); ++i) {
            const glm::dvec2 e = contour[(i + 1) % contour.size()] - contour[i];
            if (e.x == 0 && e.y == 0) continue;
            const double angle = wrapHalfTurn(std::atan2(e.y, e.x));
            const double sum = edgeProjectionSum(region, angle);
            if (std::isinf(bestSum) || sum < bestSum - 1e-12 * (1.0 + bestSum))
                best = angle, bestSum = sum;
        }
    return best;
}

std::vector<LaserVector> hatchPartsByRule(const geometry::PolygonSet& region, double spacing,
                                          const DirectionRule& rule, double power, double speed) {
    std::vector<LaserVector> vectors;
    for (const auto& part : region.parts()) {
        std::vector<geometry::Contour> contours{part.outer};
        contours.insert(contours.end(), part.holes.begin(), part.holes.end());
        const geometry::PolygonSet one =
            geometry::PolygonSet::fromContours(contours, geometry::FillRule::EvenOdd);
        std::vector<LaserVector> lines =
            hatchRegion(one, spacing, scanDirection(one, rule), power, speed);
        vectors.insert(vectors.end(), lines.begin(), lines.end());
    }
    return vectors;
}

}  // namespace vpsim::plan
