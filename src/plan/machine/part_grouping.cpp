#include "vpsim/plan/machine/part_grouping.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace vpsim::plan {
namespace {

struct Segment {
    glm::dvec2 a, b;
};

double pointSegmentDistance(const glm::dvec2& p, const Segment& s) {
    const glm::dvec2 ab = s.b - s.a;
    const double len2 = ab.x * ab.x + ab.y * ab.y;
    const double t =
        len2 > 0 ? std::clamp(((p.x - s.a.x) * ab.x + (p.y - s.a.y) * ab.y) / len2, 0.0, 1.0) : 0;
    const glm::dvec2 q = s.a + t * ab;
    return std::hypot(p.x - q.x, p.y - q.y);
}

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

double segmentDistance(const Segment& s, const Segment& t) {
    const double d1 = cross(s.a, s.b, t.a), d2 = cross(s.a, s.b, t.b);
    const double d3 = cross(t.a, t.b, s.a), d4 = cross(t.a, t.b, s.b);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
        return 0.0;  // proper crossing
    return std::min({pointSegmentDistance(s.a, t), pointSegmentDistance(s.b, t),
                     pointSegmentDistance(t.a, s), pointSegmentDistance(t.b, s)});
}

struct UnionFind {
    std::vector<int> parent;
    explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int x) {
        while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
        return x;
    }
    void unite(int a, int b) {
        a = find(a), b = find(b);
        if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
    }
};

std::vector<Segment> layerSegments(const LayerPlan& layer) {
    std::vector<Segment> segments;
    for (const auto& v : layer.vectors) segments.push_back({{v.x0, v.y0}, {v.x1, v.y1}});
    for (const auto& p : layer.points) segments.push_back({{p.x, p.y}, {p.x, p.y}});
    return segments;
}

/// Component label of each segment (joined when within `gap`), through a uniform grid.
std::vector<int> proximityLabels(const std::vector<Segment>& segments, double gap) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (const auto& s : segments)
        for (const auto& p : {s.a, s.b})
            lo[0] = std::min(lo[0], p.x), lo[1] = std::min(lo[1], p.y),
            hi[0] = std::max(hi[0], p.x), hi[1] = std::max(hi[1], p.y);
    const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
    const double cell = std::max({gap, extent / 2048.0, 1e-9});
    std::unordered_map<long long, std::vector<int>> grid;
    auto key = [](long long i, long long j) { return i * 4000037LL + j; };
    for (size_t k = 0; k < segments.size(); ++k) {
        const Segment& s = segments[k];
        long long i0 = (long long)std::floor((std::min(s.a.x, s.b.x) - gap - lo[0]) / cell);
        long long i1 = (long long)std::floor((std::max(s.a.x, s.b.x) + gap - lo[0]) / cell);
        long long j0 = (long long)std::floor((std::min(s.a.y, s.b.y) - gap - lo[1]) / cell);
        long long j1 = (long long)std::floor((std::max(s.a.y, s.b.y) + gap - lo[1]) / cell);
        for (long long i = i0; i <= i1; ++i)
            for (long long j = j0; j <= j1; ++j) grid[key(i, j)].push_back(int(k));
    }
    UnionFind sets(segments.size());
    for (const auto& [cellKey, members] : grid)
        for (size_t x = 0; x < members.size(); ++x)
            for (size_t y = x + 1; y < members.size(); ++y) {
                int a = members[x], b = members[y];
                if (sets.find(a) == sets.find(b)) continue;
                if (segmentDistance(segments[size_t(a)], segments[size_t(b)]) <= gap)
                    sets.unite(a, b);
            }
    std::vector<int> labels(segments.size());
    for (size_t k = 0; k < segments.size(); ++k) labels[k] = sets.find(int(k));
    return labels;
}

bool insideContour(const geometry::Contour& contour, const glm::dvec2& p) {
    bool inside = false;
    for (size_t i = 0, j = contour.size() - 1; i < contour.size(); j = i++) {
        const glm::dvec2 &a = contour[i], &b = contour[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x)
            inside = !inside;
    }
    return inside;
}

/// Looks up the region part of a point: the part containing it, else the part whose outer
/// contour is nearest. Bounding boxes skip most containment tests.
class RegionIndex {
public:
    explicit RegionIndex(const geometry::PolygonSet& region) : mParts(region.parts()) {
        for (const auto& part : mParts) {
            glm::dvec2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
            for (const auto& v : part.outer)
                lo = {std::min(lo.x, v.x), std::min(lo.y, v.y)},
                hi = {std::max(hi.x, v.x), std::max(hi.y, v.y)};
            mBoxes.push_back({lo, hi});
        }
    }

    int partOf(const glm::dvec2& p) const {
        for (size_t k = 0; k < mParts.size(); ++k) {
            const auto& [lo, hi] = mBoxes[k];
            if (p.x < lo.x || p.x > hi.x || p.y < lo.y || p.y > hi.y) continue;
            bool inside = insideContour(mParts[k].outer, p);
            for (const auto& hole : mParts[k].holes) inside = inside && !insideContour(hole, p);
            if (inside) return int(k);
        }
        int nearest = 0;
        double nearestDistance = INFINITY;
        for (size_t k = 0; k < mParts.size(); ++k) {
            const auto& outer = mParts[k].outer;
            for (size_t i = 0; i < outer.size(); ++i) {
                double d = pointSegmentDistance(p, {outer[i], outer[(i + 1) % outer.size()]});
                if (d < nearestDistance) nearestDistance = d, nearest = int(k);
            }
        }
        return nearest;
    }

private:
    const std::vector<geometry::PolygonWithHoles>& mParts;
    std::vector<std::pair<glm::dvec2, glm::dvec2>> mBoxes;
};

}  // namespace

PartGroups groupLayerParts(const LayerPlan& layer, double gap, const geometry::PolygonSet* region) {
    const std::vector<Segment> segments = layerSegments(layer);
    std::vector<int> labels(segments.size());
    if (region && !region->empty()) {
        const RegionIndex index(*region);
        for (size_t k = 0; k < segments.size(); ++k)
            labels[k] = index.partOf(0.5 * (segments[k].a + segments[k].b));
    } else if (!segments.empty()) {
        labels = proximityLabels(segments, gap);
    }
    // Number the parts by the region's order, or by first appearance in the plan.
    std::vector<int> distinct = labels;
    if (!(region && !region->empty())) {
        std::vector<int> firstSeen;
        std::unordered_map<int, int> seen;
        for (int l : labels)
            if (seen.emplace(l, 0).second) firstSeen.push_back(l);
        distinct = firstSeen;
    } else {
        std::sort(distinct.begin(), distinct.end());
        distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    }
    std::unordered_map<int, int> index;
    for (size_t k = 0; k < distinct.size(); ++k) index[distinct[k]] = int(k);
    PartGroups groups;
    groups.vectors.resize(distinct.size());
    groups.points.resize(distinct.size());
    for (size_t k = 0; k < segments.size(); ++k) {
        int part = index[labels[k]];
        if (k < layer.vectors.size())
            groups.vectors[size_t(part)].push_back(int(k));
        else
            groups.points[size_t(part)].push_back(int(k - layer.vectors.size()));
    }
    return groups;
}

}  // namespace vpsim::plan
