/// The stack-aware ACES contour rule (aces.h, acesStackContourOffset): the edge offset that puts
/// the cured wall on the model's wall on average, counting what the layers above really send
/// into the layer (a taper's narrower layers send little to the wall, an overhang's wider ones
/// much) and the wall's slope through the layer's depth, instead of the steady state of
/// identical layers that acesContourDistance() assumes.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "aces_internal.h"

namespace vpsim::plan {
namespace {

/// The half-field profile tabulated in y (units of W) on [-Y, Y], linearly interpolated.
class ProfileTable {
public:
    explicit ProfileTable(double hatchRatio) : mValues(COUNT) {
        for (int i = 0; i < COUNT; ++i)
            mValues[i] = detail::halfFieldProfile(-LIMIT + i * STEP, hatchRatio);
    }
    double operator()(double y) const {
        double u = (std::clamp(y, -LIMIT, LIMIT) + LIMIT) / STEP;
        int i = std::min(int(u), COUNT - 2);
        double f = u - i;
        return mValues[i] * (1 - f) + mValues[i + 1] * f;
    }

private:
    static constexpr double LIMIT = 6.0, STEP = 0.005;
    static constexpr int COUNT = int(2 * LIMIT / STEP) + 1;
    std::vector<double> mValues;
};

struct WallSample {
    glm::dvec2 point, normal;  ///< on the contour; outward from the solid
    double weight = 0;         ///< contour length it stands for (mm)
};

/// Points along every contour, at most about 256 in all and at least W/4 apart.
std::vector<WallSample> wallSamples(const geometry::PolygonSet& region, double beamRadius) {
    const double spacing = std::max(region.perimeter() / 256.0, 0.25 * beamRadius);
    std::vector<WallSample> samples;
    for (const auto& contour : region.contours())  // outers CCW, holes CW: right is outward
        for (size_t i = 0; i < contour.size(); ++i) {
            const glm::dvec2 a = contour[i], b = contour[(i + 1) % contour.size()];
            const double length = glm::length(b - a);
            if (!(length > 0)) continue;
            const glm::dvec2 d = (b - a) / length, normal{d.y, -d.x};
            const int n = std::max(1, int(std::ceil(length / spacing)));
            for (int s = 0; s < n; ++s)
                samples.push_back({a + (s + 0.5) / n * (b - a), normal, length / n});
        }
    return samples;
}

/// Signed distance (mm) of `p` from the boundary of `region`: positive outside.
double signedDistance(const geometry::PolygonSet& region, const glm::dvec2& p) {
    double best = 1e300;
    for (const auto& contour : region.contours())
        for (size_t i = 0; i < contour.size(); ++i) {
            const glm::dvec2 a = contour[i], ab = contour[(i + 1) % contour.size()] - a;
            const double len2 = glm::dot(ab, ab);
            const double f = len2 > 0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
            best = std::min(best, glm::length(p - (a + f * ab)));
        }
    if (best == 1e300) return 1e300;
    return region.contains(p) ? -best : best;
}

/// The model's wall at height h above the slicing plane, relative to the plane's contour
/// (outward mm): linear toward the neighbour's contour if it is a slope, else vertical.
double modelWall(double h, const AcesNeighbour* neighbour, double signedToIt) {
    if (!neighbour || !(std::abs(signedToIt) <= 1.75 * neighbour->distance)) return 0.0;
    return -signedToIt * std::abs(h) / neighbour->distance;
}

}  // namespace

double acesStackContourOffset(const AcesParameters& p, const geometry::PolygonSet& region,
                              double hatchRatio, double targetDose, const AcesStack& stack,
                              double* scallop) {
    const double W = p.beamRadius, De = p.attenuationLength, zmax = p.depthOfMaximum;
    const ProfileTable profile(hatchRatio);
    const std::vector<WallSample> samples = wallSamples(region, W);
    // Outward positions t of the wall searched on [-T, T]; the own line field's tail and what
    // the layers above send there, per sample.
    const int steps = 161;
    const double T = 2.5 * W, dt = 2 * T / (steps - 1);
    const int depths = 8;
    const double depthRange = p.layerThickness - zmax;
    std::vector<double> sent(samples.size() * steps, 0.0), wall(samples.size() * depths, 0.0);
    const AcesNeighbour* up = stack.above.empty() ? nullptr : &stack.above.front();
    const AcesNeighbour* down = stack.below ? &*stack.below : nullptr;
    for (size_t s = 0; s < samples.size(); ++s) {
        const WallSample& w = samples[s];
        for (const AcesNeighbour& a : stack.above) {
            const double sd = signedDistance(*a.region, w.point), gain = std::exp(-a.distance / De);
            for (int i = 0; i < steps; ++i)
                sent[s * steps + i] += gain * profile((sd + (-T + i * dt) + a.edgeOffset) / W);
        }
        const double sdUp = up ? signedDistance(*up->region, w.point) : 0.0;
        const double sdDown = down ? signedDistance(*down->region, w.point) : 0.0;
        for (int m = 0; m < depths; ++m) {
            const double h = 0.5 * p.layerThickness - (zmax + (m + 0.5) / depths * depthRange);
            wall[s * depths + m] = h > 0 ? modelWall(h, up, sdUp) : modelWall(h, down, sdDown);
        }
    }
    std::vector<double> levels(depths), meanByDepth(depths);
    for (int m = 0; m < depths; ++m)
        levels[m] =
            std::clamp(p.criticalDose / targetDose * std::exp((m + 0.5) / depths * depthRange / De),
                       1e-6, 0.97);
    double totalWeight = 0;
    for (const auto& w : samples) totalWeight += w.weight * depths;
    // Mean signed distance of the cured wall from the model's wall for edge offset e (mm):
    // the outermost grid position where the exposure still reaches the depth's level.
    std::vector<double> field(steps);
    auto meanError = [&](double e) {
        double sum = 0;
        std::fill(meanByDepth.begin(), meanByDepth.end(), 0.0);
        for (size_t s = 0; s < samples.size(); ++s) {
            for (int i = 0; i < steps; ++i)
                field[i] = profile((-T + i * dt + e) / W) + sent[s * steps + i];
            for (int m = 0; m < depths; ++m) {
                int i = steps - 1;
                while (i >= 0 && field[i] < levels[m]) --i;
                double t = i < 0 ? -T : i == steps - 1 ? T : -T + i * dt;
                if (i >= 0 && i < steps - 1)  // linear between the last cured and first not
                    t += dt * (field[i] - levels[m]) / (field[i] - field[i + 1]);
                sum += samples[s].weight * (t - wall[s * depths + m]);
                meanByDepth[m] += samples[s].weight * depths * t / totalWeight;
            }
        }
        return sum / totalWeight;
    };
    double lo = 0, hi = 3 * W;  // the error falls as the offset grows
    double e = meanError(lo) <= 0 ? lo : meanError(hi) >= 0 ? hi : -1;
    if (e < 0) {
        for (int i = 0; i < 30; ++i) {  // 3 W / 2^30: far below a nanometre
            double mid = 0.5 * (lo + hi);
            (meanError(mid) > 0 ? lo : hi) = mid;
        }
        e = 0.5 * (lo + hi);
    }
    meanError(e);
    if (scallop) {
        auto [nearest, farthest] = std::minmax_element(meanByDepth.begin(), meanByDepth.end());
        *scallop = 0.5 * (*farthest - *nearest);
    }
    return e;
}

}  // namespace vpsim::plan
