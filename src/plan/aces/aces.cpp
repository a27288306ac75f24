#include "vpsim/plan/aces/aces.h"
#include "internal.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/core/text.h"

namespace vpsim::plan {
namespace {

/// Exposure of a field of lines at positions l * rh (l from lFirst to lLast) at y, in units
/// where a single line peaks at sqrt(2/pi) and the infinite field averages 1/rh (y, rh in W).
double fieldExposure(double y, double rh, long lFirst, long lLast) {
    double sum = 0;
    for (long l = lFirst; l <= lLast; ++l) {
        double d = y - double(l) * rh;
        sum += std::exp(-2.0 * d * d);
    }
    return std::sqrt(2.0 / M_PI) * sum;
}

glm::dvec2 rotate(const glm::dvec2& p, double angle) {
    double c = std::cos(angle), s = std::sin(angle);
    return {c * p.x - s * p.y, s * p.x + c * p.y};
}

}  // namespace

double detail::halfFieldProfile(double y, double hatchRatio) {
    const long reach = long(std::ceil(6.0 / hatchRatio)) + 2;
    return fieldExposure(y, hatchRatio, -reach, 0) * hatchRatio;
}

double acesTargetDose(double criticalDose, double layerThickness, double depthOfMaximum,
                      double attenuationLength) {
    double h = layerThickness - depthOfMaximum;
    return criticalDose / std::exp(-std::max(h, 0.0) / attenuationLength);
}

double acesRipple(double hatchRatio) {
    const double rh = hatchRatio;
    const long reach = long(std::ceil(4.0 / rh)) + 2;  // lines beyond 4 W contribute < e^-32
    const int samples = 256;
    double sum = 0, sumSq = 0;
    for (int s = 0; s < samples; ++s) {
        double e = fieldExposure((s + 0.5) / samples * rh, rh, -reach, reach);
        sum += e;
        sumSq += e * e;
    }
    double mean = sum / samples;
    return std::sqrt(std::max(0.0, sumSq / samples - mean * mean)) / mean;
}

double acesHatchRatio(double homogeneity) {
    if (!(homogeneity > 0))
        throw InputError("ACES homogeneity (relative standard deviation) must be positive");
    double lo = 0.05, hi = 3.0;
    if (acesRipple(hi) <= homogeneity) return hi;
    for (int i = 0; i < 60; ++i) {  // the ripple grows monotonically with rh on this range
        double mid = 0.5 * (lo + hi);
        (acesRipple(mid) <= homogeneity ? lo : hi) = mid;
    }
    return lo;
}

double acesEdgeDistance(double hatchRatio, double fraction) {
    const double rh = hatchRatio, plateau = 1.0 / rh;
    const long reach = long(std::ceil(6.0 / rh)) + 2;
    auto relative = [&](double y) { return fieldExposure(y, rh, -reach, 0) / plateau; };
    double lo = -2.0, hi = 4.0;  // relative(lo) > fraction > relative(hi) for fractions in (0, 0.5)
    for (int i = 0; i < 80; ++i) {
        double mid = 0.5 * (lo + hi);
        (relative(mid) > fraction ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double acesContourDistance(double hatchRatio, double surfaceFraction, double depthRatio,
                           double printThrough, double* scallop) {
    // The wall at depth d lies where the layer's relative surface exposure reaches
    // (Ec/Etar) exp(d/De) / printThrough; below the plateau's ripple the profile is monotonic.
    const int depths = 32;
    double sum = 0, nearest = 1e300, farthest = -1e300;
    for (int k = 0; k < depths; ++k) {
        double d = (k + 0.5) / depths * depthRatio;
        double level = std::clamp(surfaceFraction * std::exp(d) / printThrough, 1e-6, 0.97);
        double y = acesEdgeDistance(hatchRatio, level);
        sum += y;
        nearest = std::min(nearest, y);
        farthest = std::max(farthest, y);
    }
    if (scallop) *scallop = 0.5 * (farthest - nearest);
    return sum / depths;
}

double longestEdgeDirection(const geometry::PolygonSet& region) {
    double best = -1, direction = 0;
    for (const auto& contour : region.contours())
        for (size_t i = 0; i < contour.size(); ++i) {
            glm::dvec2 d = contour[(i + 1) % contour.size()] - contour[i];
            double length = std::hypot(d.x, d.y);
            if (length > best + 1e-12) {
                best = length;
                direction = std::atan2(d.y, d.x);
            }
        }
    direction = std::fmod(direction + 2 * M_PI, M_PI);
    return direction;
}

AcesDesign designAces(const AcesParameters& p, const geometry::PolygonSet& region,
                      const AcesStack* stack) {
    if (!(p.beamRadius > 0) || !(p.attenuationLength > 0) || !(p.criticalDose > 0) ||
        !(p.layerThickness > 0) || !(p.laserPower > 0))
        throw InputError(
            "ACES needs a positive beam radius, attenuation length, critical dose, layer thickness "
            "and laser power");
    if (region.empty()) throw InputError("ACES: the layer region is empty");
    AcesDesign design;
    design.targetDose =
        acesTargetDose(p.criticalDose, p.layerThickness, p.depthOfMaximum, p.attenuationLength);
    design.direction = p.direction ? *p.direction : longestEdgeDirection(region);
    if (p.borderCount < 0) throw InputError("ACES border count must be >= 0");
    if (p.borderOffset && !(*p.borderOffset >= 0))
        throw InputError("ACES border offset must be >= 0");
    design.beamRadius = p.beamRadius;
    design.borderCount = p.borderCount;
    const double maxRatio = acesHatchRatio(p.homogeneity), maxSpacing = maxRatio * p.beamRadius;
    const double depthRatio = (p.layerThickness - p.depthOfMaximum) / p.attenuationLength;
    const double printThrough =
        p.steadyPrintThrough ? 1.0 / (1.0 - std::exp(-p.layerThickness / p.attenuationLength))
                             : 1.0;
    // The offset depends on the spacing and the spacing (a whole number of spaces across the
    // field, Eq. 15) on the offset: two rounds settle both to well below a micrometre.
    design.hatchSpacing = maxSpacing;
    for (int round = 0; round < 2; ++round) {
        double rh = design.hatchSpacing / p.beamRadius, scallop = 0;
        if (p.borderOffset)
            design.edgeOffset = *p.borderOffset;
        else if (p.edge == AcesEdge::SeedFivePercent)
            design.edgeOffset = acesEdgeDistance(rh, 0.05) * p.beamRadius;
        else if (stack)
            design.edgeOffset =
                acesStackContourOffset(p, region, rh, design.targetDose, *stack, &scallop);
        else
            design.edgeOffset = acesContourDistance(rh, p.criticalDose / design.targetDose,
                                                    depthRatio, printThrough, &scallop) *
                                p.beamRadius;
        design.scallop = stack ? scallop : scallop * p.beamRadius;
        geometry::PolygonSet field = region.offset(-design.edgeOffset);
        double lo = 1e300, hi = -1e300;
        for (const auto& contour : field.contours())
            for (const auto& v : contour) {
                double across = rotate(v, -design.direction).y;
                lo = std::min(lo, across);
                hi = std::max(hi, across);
            }
        double width = hi > lo ? hi - lo : 0.0;
        design.hatchSpacing = width > 0 ? width / std::ceil(width / maxSpacing) : maxSpacing;
    }
    const double rh = design.hatchSpacing / p.beamRadius;
    design.ripple = acesRipple(rh);
    // Relative exposure at the contour: the half field's profile at the edge offset.
    const long reach = long(std::ceil(6.0 / rh)) + 2;
    design.wallLevel = fieldExposure(design.edgeOffset / p.beamRadius, rh, -reach, 0) * rh;
    design.speed = p.laserPower / (design.targetDose * design.hatchSpacing);  // Eq. C.9
    return design;
}

std::vector<LaserVector> hatchRegion(const geometry::PolygonSet& region, double spacing,
                                     double direction, double power, double speed,
                                     const geometry::PolygonSet* clip) {
    if (!(spacing > 0) || !(speed > 0))
        throw InputError("hatching needs a positive spacing and speed");
    auto rotatedContours = [&](const geometry::PolygonSet& set) {
        std::vector<geometry::Contour> contours = set.contours();
        for (auto& contour : contours)
            for (auto& v : contour) v = rotate(v, -direction);  // scan lines become horizontal
        return contours;
    };
    double lo = 1e300, hi = -1e300;
    for (const auto& contour : rotatedContours(region))
        for (const auto& v : contour) lo = std::min(lo, v.y), hi = std::max(hi, v.y);
    const std::vector<geometry::Contour> contours = rotatedContours(clip ? *clip : region);
    std::vector<LaserVector> vectors;
    if (!(hi > lo)) return vectors;
    // designAces makes the width a whole number of spaces, but Clipper rounds offset contours to
    // 1 nm: allow 1% of a space before dropping the last line (it is clamped into the field).
    long lines = long(std::floor((hi - lo) / spacing + 0.01)) + 1;
    const double nudge =
        1e-9 * std::max(1.0, hi - lo);  // keep the extreme lines off horizontal edges
    std::vector<double> xs;
    for (long k = 0; k < lines; ++k) {
        double y = std::clamp(lo + k * spacing, lo + nudge, hi - nudge);
        xs.clear();
        for (const auto& contour : contours)
            for (size_t i = 0; i < contour.size(); ++i) {
                const glm::dvec2 &a = contour[i], &b = contour[(i + 1) % contour.size()];
                if ((a.y <= y) != (b.y <= y))
                    xs.push_back(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
            }
        std::sort(xs.begin(), xs.end());
        bool reverse = k % 2 == 1;
        std::vector<LaserVector> row;
        for (size_t i = 0; i + 1 < xs.size(); i += 2) {
            glm::dvec2 a = rotate({xs[i], y}, direction), b = rotate({xs[i + 1], y}, direction);
            if (reverse) std::swap(a, b);
            row.push_back({a.x, a.y, b.x, b.y, power, speed});
        }
        if (reverse) std::reverse(row.begin(), row.end());
        vectors.insert(vectors.end(), row.begin(), row.end());
    }
    return vectors;
}

std::vector<LaserVector> contourLoops(const geometry::PolygonSet& region, double power,
                                      double speed) {
    std::vector<LaserVector> loops;
    for (const auto& contour : region.contours())
        for (size_t i = 0; i < contour.size(); ++i) {
            const glm::dvec2 &a = contour[i], &b = contour[(i + 1) % contour.size()];
            loops.push_back({a.x, a.y, b.x, b.y, power, speed});
        }
    return loops;
}

LayerPlan planAcesLayer(const geometry::PolygonSet& region, const AcesDesign& design,
                        double laserPower, double z, AcesLayerInfo* info) {
    LayerPlan layer;
    layer.z = z;
    AcesLayerInfo local;
    for (int k = 0; k < design.borderCount; ++k) {
        auto loops = contourLoops(region.offset(-(design.edgeOffset + k * design.hatchSpacing)),
                                  laserPower, design.speed);
        layer.vectors.insert(layer.vectors.end(), loops.begin(), loops.end());
    }
    geometry::PolygonSet field =
        region.offset(-(design.edgeOffset + design.borderCount * design.hatchSpacing));
    // Line ends stop half a spacing short of the outermost line (border loop or imaginary line):
    // along the lines the field is a continuous sheet, which a line field matches when it
    // reaches half a spacing beyond its last line (the edge offset's definition).
    geometry::PolygonSet clip =
        region.offset(-(design.edgeOffset + (design.borderCount - 0.5) * design.hatchSpacing));
    auto hatch =
        hatchRegion(field, design.hatchSpacing, design.direction, laserPower, design.speed, &clip);
    layer.vectors.insert(layer.vectors.end(), hatch.begin(), hatch.end());
    if (design.beamRadius > 0) detail::planSmallFeatures(region, design, laserPower, layer, local);
    if (!region.empty() && layer.vectors.empty() && layer.points.empty()) {
        local.unexposed = true;
        logWarn("ACES: the layer region at z = " + formatQuantity(z) + " mm (" +
                formatQuantity(region.area()) + " mm^2) gets no exposure");
    }
    if (info) *info = local;
    return layer;
}

}  // namespace vpsim::plan
