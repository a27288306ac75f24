/// Small features of an ACES layer: what the inward offset of the line field removes (strips
/// narrower than two edge offsets, spikes, specks) still gets a line or a spot, sized so that the
/// feature's half-width reaches the design's wall level and its middle at least Etar.
#include <algorithm>
#include <cmath>

#include "internal.h"

namespace vpsim::plan {

geometry::PolygonSet smallFeatures(const geometry::PolygonSet& region, double edgeOffset,
                                   double beamRadius) {
    geometry::PolygonSet opened = region.offset(-edgeOffset).offset(edgeOffset + 0.5 * beamRadius);
    geometry::PolygonSet lost = region.difference(opened);
    std::vector<geometry::Contour> kept;
    const double minArea = 0.01 * beamRadius * beamRadius;
    for (const auto& part : lost.parts()) {
        if (part.area() < minArea) continue;
        kept.push_back(part.outer);
        kept.insert(kept.end(), part.holes.begin(), part.holes.end());
    }
    return geometry::PolygonSet::fromContours(kept, geometry::FillRule::EvenOdd);
}

namespace detail {
namespace {

/// Largest inward offset (mm) that leaves `piece` non-empty (its inradius), to 1% of `upper`.
double inradius(const geometry::PolygonSet& piece, double upper) {
    double lo = 0, hi = upper;
    if (!piece.offset(-hi).empty()) return hi;
    for (int i = 0; i < 12; ++i) {
        double mid = 0.5 * (lo + hi);
        (piece.offset(-mid).empty() ? hi : lo) = mid;
    }
    return lo;
}

}  // namespace

void planSmallFeatures(const geometry::PolygonSet& region, const AcesDesign& design,
                       double laserPower, LayerPlan& layer, AcesLayerInfo& info) {
    const double w = design.beamRadius, etar = design.targetDose;
    const double wall = std::max(design.wallLevel, 0.01) * etar;
    geometry::PolygonSet features = smallFeatures(region, design.edgeOffset, w);
    for (const auto& part : features.parts()) {
        geometry::PolygonSet piece = geometry::PolygonSet::fromContours({part.outer});
        double r = inradius(piece, design.edgeOffset + design.hatchSpacing);
        // Peak exposure that puts the wall level at the half-width r, and at least Etar so the
        // feature is cured through the layer.
        double peak = std::max(wall * std::exp(2.0 * r * r / (w * w)), etar);
        geometry::PolygonSet core = piece.offset(-0.9 * r);
        if (core.empty()) core = piece;
        auto [lo, hi] = core.bounds();
        double direction = longestEdgeDirection(piece);
        glm::dvec2 extent = hi - lo;
        if (std::max(extent.x, extent.y) < design.hatchSpacing) {
            // A spot: a dot of energy E peaks at 2 E / (pi W^2) (the normalised Gaussian).
            glm::dvec2 c = 0.5 * (lo + hi);
            layer.points.push_back({c.x, c.y, peak * M_PI * w * w / 2.0});
            ++info.smallFeatureSpots;
            continue;
        }
        // A line along the feature through the middle of its core: a single line of P/V mJ/mm
        // peaks at sqrt(2/pi) P / (W V) (Eq. C.6).
        double speed = std::sqrt(2.0 / M_PI) * laserPower / (w * peak);
        geometry::PolygonSet rotatedCore = core.rotated(-direction);
        auto [rlo, rhi] = rotatedCore.bounds();
        double y = 0.5 * (rlo.y + rhi.y);
        auto intervals = rotatedCore.intervalsAt(y);
        if (intervals.empty()) {  // a core thinner than the rounding: take the piece's middle
            auto [plo, phi] = piece.rotated(-direction).bounds();
            intervals = piece.rotated(-direction).intervalsAt(0.5 * (plo.y + phi.y));
            y = 0.5 * (plo.y + phi.y);
        }
        for (const auto& [x0, x1] : intervals) {
            double c = std::cos(direction), s = std::sin(direction);
            layer.vectors.push_back({c * x0 - s * y, s * x0 + c * y, c * x1 - s * y, s * x1 + c * y,
                                     laserPower, speed});
        }
        ++info.smallFeatureLines;
    }
}

}  // namespace detail
}  // namespace vpsim::plan
