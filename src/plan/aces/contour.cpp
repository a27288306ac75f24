/// The stack-aware ACES contour rule (aces.h, acesStackContourOffset): the edge offset that puts
/// the cured wall on the model's wall on average, counting what the layers above really send
/// into the layer (a taper's narrower layers send little to the wall, an overhang's wider ones
/// much) and the wall's slope through the layer's depth, instead of the steady state of
/// identical layers that acesContourDistance() assumes.
#include <algorithm>
#include <cmath>
#include <deque>
#include <utility>

#include <glm/geometric.hpp>

#include "internal.h"

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

/// The table of a hatch ratio, kept for the last few ratios asked for on this thread: a part's
/// layers mostly share the two ratios of acesDesign's two rounds, and a table is 2401 sums of
/// Gaussians.
const ProfileTable& profileTable(double hatchRatio) {
    thread_local std::deque<std::pair<double, ProfileTable>> tables;
    for (const auto& [ratio, table] : tables)
        if (ratio == hatchRatio) return table;
    if (tables.size() == 4) tables.pop_front();
    tables.emplace_back(hatchRatio, ProfileTable(hatchRatio));
    return tables.back().second;
}

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

/// The wall problem of one layer, tabulated once: per contour sample, what the layers above
/// send at outward positions t on [-T, T] and the model's wall at each depth sample.
struct WallTables {
    static constexpr int STEPS = 161, DEPTHS = 8;
    double W = 0, T = 0, dt = 0, totalWeight = 0;
    std::vector<WallSample> samples;
    std::vector<double> sent, wall, levels;
};

WallTables tabulate(const AcesParameters& p, const geometry::PolygonSet& region,
                    const ProfileTable& profile, double targetDose, const AcesStack& stack) {
    const int steps = WallTables::STEPS, depths = WallTables::DEPTHS;
    const double De = p.attenuationLength, zmax = p.depthOfMaximum;
    const double depthRange = p.layerThickness - zmax;
    WallTables w;
    w.W = p.beamRadius;
    w.T = 2.5 * w.W;
    w.dt = 2 * w.T / (steps - 1);
    w.samples = wallSamples(region, w.W);
    w.sent.assign(w.samples.size() * steps, 0.0);
    w.wall.assign(w.samples.size() * depths, 0.0);
    const AcesNeighbour* up = stack.above.empty() ? nullptr : &stack.above.front();
    const AcesNeighbour* down = stack.below ? &*stack.below : nullptr;
    std::vector<double> gains;  // each layer above's attenuation down to this one
    for (const AcesNeighbour& a : stack.above) gains.push_back(std::exp(-a.distance / De));
    for (size_t s = 0; s < w.samples.size(); ++s) {
        const glm::dvec2 point = w.samples[s].point;
        for (size_t k = 0; k < stack.above.size(); ++k) {
            const AcesNeighbour& a = stack.above[k];
            const double sd = signedDistance(*a.region, point), gain = gains[k];
            for (int i = 0; i < steps; ++i)
                w.sent[s * steps + i] += gain * profile((sd - w.T + i * w.dt + a.edgeOffset) / w.W);
        }
        const double sdUp = up ? signedDistance(*up->region, point) : 0.0;
        const double sdDown = down ? signedDistance(*down->region, point) : 0.0;
        for (int m = 0; m < depths; ++m) {
            const double h = 0.5 * p.layerThickness - (zmax + (m + 0.5) / depths * depthRange);
            w.wall[s * depths + m] = h > 0 ? modelWall(h, up, sdUp) : modelWall(h, down, sdDown);
        }
        w.totalWeight += w.samples[s].weight * depths;
    }
    for (int m = 0; m < depths; ++m)
        w.levels.push_back(
            std::clamp(p.criticalDose / targetDose * std::exp((m + 0.5) / depths * depthRange / De),
                       1e-6, 0.97));
    return w;
}

/// Mean signed distance (mm) of the cured wall from the model's wall for edge offset e: at each
/// sample and depth, the outermost position where the exposure still reaches the depth's level.
/// `meanByDepth` receives the contour-mean wall position per depth.
double meanWallError(const WallTables& w, const ProfileTable& profile, double e,
                     std::vector<double>& meanByDepth) {
    const int steps = WallTables::STEPS, depths = WallTables::DEPTHS;
    std::vector<double> own(steps), field(steps);  // the layer's own profile: the same everywhere
    for (int i = 0; i < steps; ++i) own[i] = profile((-w.T + i * w.dt + e) / w.W);
    meanByDepth.assign(depths, 0.0);
    double sum = 0;
    for (size_t s = 0; s < w.samples.size(); ++s) {
        for (int i = 0; i < steps; ++i) field[i] = own[i] + w.sent[s * steps + i];
        int i = steps - 1;
        for (int m = 0; m < depths; ++m) {
            // Deeper levels are higher (tabulate): their last cured step is not further out, so
            // the search goes on from the level above's (the same step as from the end).
            if (m > 0 && w.levels[m] < w.levels[m - 1]) i = steps - 1;
            while (i >= 0 && field[i] < w.levels[m]) --i;
            double t = i < 0 ? -w.T : i == steps - 1 ? w.T : -w.T + i * w.dt;
            if (i >= 0 && i < steps - 1)  // linear between the last cured and first not
                t += w.dt * (field[i] - w.levels[m]) / (field[i] - field[i + 1]);
            sum += w.samples[s].weight * (t - w.wall[s * depths + m]);
            meanByDepth[m] += w.samples[s].weight * depths * t / w.totalWeight;
        }
    }
    return sum / w.totalWeight;
}

}  // namespace

double acesStackContourOffset(const AcesParameters& p, const geometry::PolygonSet& region,
                              double hatchRatio, double targetDose, const AcesStack& stack,
                              double* scallop) {
    const ProfileTable& profile = profileTable(hatchRatio);
    const WallTables w = tabulate(p, region, profile, targetDose, stack);
    std::vector<double> meanByDepth;
    auto error = [&](double e) { return meanWallError(w, profile, e, meanByDepth); };
    double lo = 0, hi = 3 * p.beamRadius;  // the error falls as the offset grows
    double e = error(lo) <= 0 ? lo : error(hi) >= 0 ? hi : -1;
    if (e < 0) {
        for (int i = 0; i < 30; ++i) {  // 3 W / 2^30: far below a nanometre
            double mid = 0.5 * (lo + hi);
            (error(mid) > 0 ? lo : hi) = mid;
        }
        e = 0.5 * (lo + hi);
    }
    error(e);
    if (scallop) {
        auto [nearest, farthest] = std::minmax_element(meanByDepth.begin(), meanByDepth.end());
        *scallop = 0.5 * (*farthest - *nearest);
    }
    return e;
}

}  // namespace vpsim::plan
