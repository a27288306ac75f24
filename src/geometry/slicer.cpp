#include "vpsim/geometry/slicer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <tbb/parallel_for.h>

#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"

namespace vpsim::geometry {
namespace {

/// A piece of contour inside one triangle: from the crossing of mesh edge `from` to the crossing
/// of mesh edge `to`, oriented so that the solid lies on the left (outer contours CCW).
struct Segment {
    uint64_t from, to;
    glm::dvec2 start;
};

uint64_t edgeKey(uint32_t a, uint32_t b) {
    return (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}

/// Crossing of edge (a, b) with the plane, computed from the lower vertex index so the two
/// triangles sharing the edge get the same bits.
glm::dvec2 crossing(const Mesh& mesh, uint32_t a, uint32_t b, double z) {
    const glm::dvec3& p = mesh.vertices[std::min(a, b)];
    const glm::dvec3& q = mesh.vertices[std::max(a, b)];
    const double t = (z - p.z) / (q.z - p.z);
    return {p.x + (q.x - p.x) * t, p.y + (q.y - p.y) * t};
}

/// Appends the triangle's segment on plane z, if it crosses. A vertex is "below" when
/// z_v <= z (plane perturbed up) or z_v < z (perturbed down): consistent for all triangles.
void addSegment(const Mesh& mesh, const std::array<uint32_t, 3>& tri, double z, bool perturbUp,
                std::vector<Segment>& out) {
    bool below[3];
    int belowCount = 0;
    for (int k = 0; k < 3; ++k) {
        const double vz = mesh.vertices[tri[k]].z;
        below[k] = perturbUp ? vz <= z : vz < z;
        belowCount += below[k];
    }
    if (belowCount == 0 || belowCount == 3) return;
    uint32_t upA = 0, upB = 0, downA = 0, downB = 0;
    for (int k = 0; k < 3; ++k) {
        const int n = (k + 1) % 3;
        if (below[k] && !below[n]) {
            upA = tri[k];
            upB = tri[n];
        } else if (!below[k] && below[n]) {
            downA = tri[k];
            downB = tri[n];
        }
    }
    // Walking the triangle's boundary counter-clockwise (seen from outside), the contour runs
    // from where it goes down through the plane to where it comes back up.
    out.push_back({edgeKey(downA, downB), edgeKey(upA, upB), crossing(mesh, downA, downB, z)});
}

std::string formatZ(double z) {
    std::ostringstream s;
    s << z;
    return s.str();
}

/// Joins segments into closed loops through their shared edge ids.
std::vector<Contour> linkSegments(std::vector<Segment>& segments, double z) {
    std::sort(segments.begin(), segments.end(),
              [](const Segment& a, const Segment& b) { return a.from < b.from; });
    std::vector<char> used(segments.size(), 0);
    std::vector<Contour> loops;
    for (size_t first = 0; first < segments.size(); ++first) {
        if (used[first]) continue;
        Contour loop;
        size_t current = first;
        for (;;) {
            used[current] = 1;
            loop.push_back(segments[current].start);
            const uint64_t next = segments[current].to;
            auto it = std::lower_bound(segments.begin(), segments.end(), next,
                                       [](const Segment& s, uint64_t key) { return s.from < key; });
            if (it == segments.end() || it->from != next) {
                throw InputError(
                    "slice at z = " + formatZ(z) + " mm: a contour does not close near (" +
                    formatZ(segments[current].start.x) + ", " + formatZ(segments[current].start.y) +
                    ") mm; the mesh is open or inconsistently oriented (check it with "
                    "'vpsim part check')");
            }
            current = size_t(it - segments.begin());
            if (current == first) break;
            if (used[current]) {
                throw InputError("slice at z = " + formatZ(z) +
                                 " mm: contours cross at a non-manifold edge");
            }
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

void checkOptions(const SliceOptions& o) {
    if (!(o.layerThickness > 0.0) || !std::isfinite(o.layerThickness)) {
        throw InputError("layer thickness must be positive, got " + formatZ(o.layerThickness) +
                         " mm");
    }
    if (!(o.planePosition >= 0.0 && o.planePosition <= 1.0)) {
        throw InputError("slicing plane position must be in [0, 1] of the layer, got " +
                         formatZ(o.planePosition));
    }
}

}  // namespace

int layerCount(const Mesh& mesh, const SliceOptions& options) {
    checkOptions(options);
    const Bounds b = mesh.bounds();
    if (b.empty()) return 0;
    const double z0 = options.zStart.value_or(b.lo.z);
    // STL vertices are float32: a 0.2 mm part is 0.200000003 mm tall, which must not add a fifth
    // 50 um layer. Heights within float32 rounding of the coordinates (6e-8 relative; 1e-6
    // leaves a margin) count as whole layers.
    const double slack = 1e-6 * std::max({std::abs(b.hi.z), std::abs(z0), 1.0});
    const double layers = std::ceil((b.hi.z - z0 - slack) / options.layerThickness - 1e-9);
    if (layers > 1e7)
        throw InputError("more than 10 million layers: is the layer thickness in mm?");
    return std::max(0, int(layers));
}

PolygonSet sliceAt(const Mesh& mesh, double z, bool perturbUp) {
    std::vector<Segment> segments;
    for (const auto& tri : mesh.triangles) addSegment(mesh, tri, z, perturbUp, segments);
    return PolygonSet::fromContours(linkSegments(segments, z), FillRule::Positive);
}

std::vector<Layer> sliceMesh(const Mesh& mesh, const SliceOptions& options,
                             const std::vector<int>& onlyLayers) {
    const int count = layerCount(mesh, options);
    const double t = options.layerThickness, f = options.planePosition;
    const double z0 = options.zStart.value_or(mesh.bounds().lo.z);
    const bool perturbUp = f <= 0.5;  // towards the middle of the layer
    auto planeZ = [&](int k) { return z0 + (k + f) * t; };

    std::vector<int> selected = onlyLayers;
    if (selected.empty()) {
        for (int k = 0; k < count; ++k) selected.push_back(k);
    }
    for (int k : selected) {
        if (k < 0 || k >= count) {
            throw InputError("layer " + std::to_string(k) + " does not exist (the part has " +
                             std::to_string(count) + " layers)");
        }
    }

    // Bucket triangles by the layers whose plane they cross (two-pass counting sort), so each
    // layer visits only its own triangles: O(triangles + crossings) overall.
    auto crosses = [&](double lo, double hi, int k) {
        const double z = planeZ(k);
        return perturbUp ? (lo <= z && z < hi) : (lo < z && z <= hi);
    };
    const size_t nTri = mesh.triangles.size();
    std::vector<std::pair<int, int>> range(nTri, {0, -1});
    std::vector<uint32_t> start(size_t(count) + 1, 0);
    for (size_t i = 0; i < nTri; ++i) {
        const auto& tri = mesh.triangles[i];
        const double lo =
            std::min({mesh.vertices[tri[0]].z, mesh.vertices[tri[1]].z, mesh.vertices[tri[2]].z});
        const double hi =
            std::max({mesh.vertices[tri[0]].z, mesh.vertices[tri[1]].z, mesh.vertices[tri[2]].z});
        int kLo = std::max(0, int(std::floor((lo - z0) / t - f)));
        int kHi = std::min(count - 1, int(std::ceil((hi - z0) / t - f)));
        while (kLo <= kHi && !crosses(lo, hi, kLo)) ++kLo;
        while (kHi >= kLo && !crosses(lo, hi, kHi)) --kHi;
        range[i] = {kLo, kHi};
        for (int k = kLo; k <= kHi; ++k) ++start[size_t(k) + 1];
    }
    for (int k = 0; k < count; ++k) start[size_t(k) + 1] += start[size_t(k)];
    std::vector<uint32_t> bucket(start.back());
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < nTri; ++i) {
        for (int k = range[i].first; k <= range[i].second; ++k)
            bucket[fill[size_t(k)]++] = uint32_t(i);
    }

    std::vector<Layer> layers(selected.size());
    Progress progress("slicing", selected.size());
    tbb::parallel_for(size_t(0), selected.size(), [&](size_t s) {
        const int k = selected[s];
        Layer& layer = layers[s];
        layer.index = k;
        layer.zBottom = z0 + k * t;
        layer.z = planeZ(k);
        std::vector<Segment> segments;
        segments.reserve(start[size_t(k) + 1] - start[size_t(k)]);
        for (uint32_t j = start[size_t(k)]; j < start[size_t(k) + 1]; ++j) {
            addSegment(mesh, mesh.triangles[bucket[j]], layer.z, perturbUp, segments);
        }
        layer.region =
            PolygonSet::fromContours(linkSegments(segments, layer.z), FillRule::Positive);
        progress.advance();
    });
    return layers;
}

}  // namespace vpsim::geometry
