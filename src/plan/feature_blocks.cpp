#include "vpsim/plan/feature_blocks.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "vpsim/core/error.h"

namespace vpsim::plan {
namespace {

double cross(const glm::dvec2& a, const glm::dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

/// The quadrilateral a + s t + u n for s in [s0, s1], u in [u0, u1].
geometry::PolygonSet band(const glm::dvec2& a, const glm::dvec2& t, const glm::dvec2& n, double s0,
                          double s1, double u0, double u1) {
    geometry::Contour c{a + s0 * t + u0 * n, a + s1 * t + u0 * n, a + s1 * t + u1 * n,
                        a + s0 * t + u1 * n};
    return geometry::PolygonSet::fromContours({c});
}

}  // namespace

double effectiveRadius(double beamRadius, double fraction) {
    return beamRadius * std::sqrt(-std::log(fraction) / 2.0);
}

FeatureBlocks disassembleFeatures(const geometry::PolygonSet& region, double roff, double reff,
                                  double beamRadius, double minTurn) {
    if (!(roff > 0) || !(reff > 0) || !(beamRadius > 0))
        throw InputError("feature disassembly needs positive Roff, Reff and beam radius");
    FeatureBlocks blocks;
    blocks.middle = region.offset(-roff);
    const double half = roff + beamRadius;
    const geometry::PolygonSet outside = region.offset(reff).difference(region);
    for (const auto& contour : region.contours()) {
        const size_t n = contour.size();
        for (size_t i = 0; i < n; ++i) {
            const glm::dvec2 &prev = contour[(i + n - 1) % n], &v = contour[i],
                             &next = contour[(i + 1) % n];
            glm::dvec2 d = next - v;
            double length = std::hypot(d.x, d.y);
            if (length <= 0) continue;
            glm::dvec2 t = d / length, normal{-t.y, t.x};
            if (length > 2 * half) {
                EdgeBlock e{v, next, t, normal, half, length - half, {}};
                e.sub[0] = band(v, t, normal, half, length - half, -reff, 0);
                e.sub[1] = band(v, t, normal, half, length - half, 0, roff);
                e.sub[2] = band(v, t, normal, half, length - half, roff, roff + reff);
                blocks.edges.push_back(std::move(e));
            }
            glm::dvec2 din = v - prev;
            double lin = std::hypot(din.x, din.y);
            if (lin <= 0) continue;
            double turn = std::atan2(cross(din / lin, t), glm::dot(din / lin, t));
            if (std::abs(turn) < minTurn) continue;
            CornerBlock c;
            c.vertex = v;
            c.convex = turn > 0;  // a left turn on a region-on-the-left contour
            c.halfSize = half;
            c.square = geometry::PolygonSet::rectangle(v - glm::dvec2(half), v + glm::dvec2(half));
            c.sub[0] = c.square.intersection(region).difference(blocks.middle);
            c.sub[1] = c.square.offset(reff, geometry::JoinType::Miter).intersection(outside);
            c.sub[2] = c.square.intersection(blocks.middle);
            blocks.corners.push_back(std::move(c));
        }
    }
    return blocks;
}

}  // namespace vpsim::plan
