#include "vpsim/geometry/mesh_check.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include <tbb/parallel_sort.h>
#include <glm/geometric.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/log.h"

namespace vpsim::geometry {
namespace {

std::string formatPoint(const glm::dvec3& p) {
    std::ostringstream s;
    s.precision(6);
    s << "(" << p.x << ", " << p.y << ", " << p.z << ") mm";
    return s.str();
}

/// One directed use of an undirected edge by a triangle.
struct HalfEdge {
    uint64_t key;  // min vertex << 32 | max vertex
    uint32_t triangle;
    bool forward;  // traversed from the smaller to the larger vertex index
};

std::vector<HalfEdge> sortedHalfEdges(const Mesh& mesh) {
    std::vector<HalfEdge> edges;
    edges.reserve(mesh.triangles.size() * 3);
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
            edges.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), t, a < b});
        }
    }
    tbb::parallel_sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
        return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;  // deterministic order
    });
    return edges;
}

glm::dvec3 edgeMidpoint(const Mesh& mesh, uint64_t key) {
    return 0.5 * (mesh.vertices[key >> 32] + mesh.vertices[key & 0xffffffffu]);
}

/// Does a ray from p along a fixed, slightly skewed direction cross triangle t? (Moller-Trumbore)
bool rayHits(const Mesh& mesh, size_t t, const glm::dvec3& p) {
    static const glm::dvec3 dir = glm::normalize(glm::dvec3(1.0, 1.234567e-4, 2.345678e-5));
    const auto& tri = mesh.triangles[t];
    const glm::dvec3 a = mesh.vertices[tri[0]], e1 = mesh.vertices[tri[1]] - a,
                     e2 = mesh.vertices[tri[2]] - a;
    const glm::dvec3 h = glm::cross(dir, e2);
    const double det = glm::dot(e1, h);
    if (std::abs(det) < 1e-300) return false;
    const glm::dvec3 s = p - a;
    const double u = glm::dot(s, h) / det;
    if (u < 0.0 || u > 1.0) return false;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(dir, q) / det;
    if (v < 0.0 || u + v > 1.0) return false;
    return glm::dot(e2, q) / det > 0.0;
}

struct Shell {
    std::vector<uint32_t> triangles;
    Bounds bounds;
    double volume = 0.0;
    int depth = 0;  // number of other shells enclosing this one
};

void addRepair(MeshReport& report, const std::string& line) {
    report.repairs.push_back(line);
    logWarn(report.file + ": repaired: " + line);
}

/// Removes triangles repeating a vertex; counts zero-area slivers with distinct vertices.
void dropDegenerateTriangles(Mesh& mesh, MeshReport& report, bool repair) {
    size_t kept = 0, dropped = 0;
    glm::dvec3 firstSliver(0.0);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
            ++dropped;
            continue;
        }
        const glm::dvec3& a = mesh.vertices[tri[0]];
        const double longest = std::max(
            {glm::length(mesh.vertices[tri[1]] - a), glm::length(mesh.vertices[tri[2]] - a),
             glm::length(mesh.vertices[tri[2]] - mesh.vertices[tri[1]])});
        if (glm::length(mesh.triangleNormal(t)) <= 1e-12 * longest * longest) {
            if (report.sliverTrianglesKept++ == 0) firstSliver = a;
        }
        mesh.triangles[kept++] = tri;
    }
    if (dropped > 0 && !repair) {
        report.problems.push_back(std::to_string(dropped) +
                                  " degenerate triangles (a vertex repeated)");
        return;
    }
    mesh.triangles.resize(kept);
    report.degenerateTrianglesDropped = dropped;
    if (dropped > 0)
        addRepair(report, "dropped " + std::to_string(dropped) +
                              " zero-area triangles (a vertex repeated)");
    if (report.sliverTrianglesKept > 0) {
        logWarn(
            report.file + ": " + std::to_string(report.sliverTrianglesKept) +
            " zero-area triangles with three distinct collinear vertices kept (removing them would "
            "open the mesh), first near " +
            formatPoint(firstSliver));
    }
}

/// Counts open and non-manifold edges; fills neighbour lists for manifold edges.
void checkEdges(const Mesh& mesh, MeshReport& report,
                std::vector<std::array<int64_t, 3>>& neighbours,
                std::vector<std::array<bool, 3>>& sameDirection) {
    const std::vector<HalfEdge> edges = sortedHalfEdges(mesh);
    neighbours.assign(mesh.triangles.size(), {-1, -1, -1});
    sameDirection.assign(mesh.triangles.size(), {false, false, false});
    uint64_t firstOpen = 0, firstNonManifold = 0;
    auto link = [&](const HalfEdge& x, const HalfEdge& y) {
        for (auto& n : neighbours[x.triangle]) {
            if (n < 0) {
                n = y.triangle;
                sameDirection[x.triangle][&n - neighbours[x.triangle].data()] =
                    x.forward == y.forward;
                return;
            }
        }
    };
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j].key == edges[i].key) ++j;
        if (j - i == 1 && report.openEdges++ == 0) firstOpen = edges[i].key;
        if (j - i > 2 && report.nonManifoldEdges++ == 0) firstNonManifold = edges[i].key;
        if (j - i == 2) {
            link(edges[i], edges[i + 1]);
            link(edges[i + 1], edges[i]);
        }
        i = j;
    }
    if (report.openEdges > 0) {
        report.problems.push_back(std::to_string(report.openEdges) +
                                  " open edges (mesh is not watertight), first near " +
                                  formatPoint(edgeMidpoint(mesh, firstOpen)));
    }
    if (report.nonManifoldEdges > 0) {
        report.problems.push_back(
            std::to_string(report.nonManifoldEdges) +
            " non-manifold edges (shared by more than two triangles), first near " +
            formatPoint(edgeMidpoint(mesh, firstNonManifold)));
    }
}

/// Flood-fills a consistent orientation per connected shell. flip[t] says whether triangle t
/// must be reversed to agree with its shell's first triangle.
std::vector<Shell> orientShells(const Mesh& mesh,
                                const std::vector<std::array<int64_t, 3>>& neighbours,
                                const std::vector<std::array<bool, 3>>& sameDirection,
                                std::vector<char>& flip, MeshReport& report) {
    std::vector<Shell> shells;
    std::vector<char> seen(mesh.triangles.size(), 0);
    flip.assign(mesh.triangles.size(), 0);
    std::vector<uint32_t> stack;
    for (uint32_t seed = 0; seed < mesh.triangles.size(); ++seed) {
        if (seen[seed]) continue;
        Shell shell;
        seen[seed] = 1;
        stack.push_back(seed);
        bool orientable = true;
        while (!stack.empty()) {
            const uint32_t t = stack.back();
            stack.pop_back();
            shell.triangles.push_back(t);
            for (int k = 0; k < 3; ++k) {
                const int64_t n = neighbours[t][k];
                if (n < 0) continue;
                // Neighbours traversing the shared edge the same way disagree in orientation.
                const char want = char(flip[t] ^ char(sameDirection[t][k]));
                if (!seen[n]) {
                    seen[n] = 1;
                    flip[n] = want;
                    stack.push_back(uint32_t(n));
                } else if (flip[n] != want) {
                    orientable = false;
                }
            }
        }
        if (!orientable) {
            report.problems.push_back("a shell is not orientable (Moebius-like), near " +
                                      formatPoint(mesh.vertices[mesh.triangles[seed][0]]));
        }
        shells.push_back(std::move(shell));
    }
    return shells;
}

/// Signed volume of a shell with the flood-fill orientation applied.
double shellVolume(const Mesh& mesh, const Shell& shell, const std::vector<char>& flip) {
    const glm::dvec3 c = 0.5 * (shell.bounds.lo + shell.bounds.hi);
    double sum = 0.0;
    for (uint32_t t : shell.triangles) {
        const auto& tri = mesh.triangles[t];
        const double v = glm::dot(mesh.vertices[tri[0]] - c,
                                  glm::cross(mesh.vertices[tri[1]] - c, mesh.vertices[tri[2]] - c));
        sum += flip[t] ? -v : v;
    }
    return sum / 6.0;
}

bool boundsInside(const Bounds& inner, const Bounds& outer) {
    return glm::all(glm::greaterThanEqual(inner.lo, outer.lo)) &&
           glm::all(glm::lessThanEqual(inner.hi, outer.hi));
}

/// Nesting depth of each shell by ray parity; an odd depth is a cavity (oriented inward). A shell
/// counts as inside another only when all of seven probes on it say so: a shell that
/// merely overlaps another (a self-intersecting union, common in exported STL) stays an outer.
void computeDepths(const Mesh& mesh, std::vector<Shell>& shells) {
    for (size_t i = 0; i < shells.size(); ++i) {
        // Probes: a triangle centroid and the shell's extreme vertices along +-x, +-y, +-z
        // (a shell poking out of another has some extreme point outside it).
        const auto& own = shells[i].triangles;
        const auto& first = mesh.triangles[own.front()];
        std::vector<glm::dvec3> probes{
            (mesh.vertices[first[0]] + mesh.vertices[first[1]] + mesh.vertices[first[2]]) / 3.0};
        for (int axis = 0; axis < 3; ++axis) {
            glm::dvec3 lo = mesh.vertices[first[0]], hi = lo;
            for (uint32_t t : own) {
                for (uint32_t v : mesh.triangles[t]) {
                    if (mesh.vertices[v][axis] < lo[axis]) lo = mesh.vertices[v];
                    if (mesh.vertices[v][axis] > hi[axis]) hi = mesh.vertices[v];
                }
            }
            probes.push_back(lo);
            probes.push_back(hi);
        }
        for (size_t j = 0; j < shells.size(); ++j) {
            if (j == i || !boundsInside(shells[i].bounds, shells[j].bounds)) continue;
            int inside = 0;
            for (const auto& probe : probes) {
                size_t hits = 0;
                for (uint32_t t : shells[j].triangles) hits += rayHits(mesh, t, probe) ? 1 : 0;
                inside += int(hits % 2);
            }
            if (inside == int(probes.size())) ++shells[i].depth;
        }
    }
}

}  // namespace

size_t mergeDuplicateVertices(Mesh& mesh) {
    struct Key {
        double x, y, z;
        uint32_t index;
        bool samePlace(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    const size_t n = mesh.vertices.size();
    std::vector<Key> keys(n);
    for (uint32_t i = 0; i < n; ++i) {
        const glm::dvec3 v = mesh.vertices[i] + glm::dvec3(0.0);  // -0 + 0 == +0
        keys[i] = {v.x, v.y, v.z, i};
    }
    tbb::parallel_sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
        if (a.x != b.x) return a.x < b.x;
        if (a.y != b.y) return a.y < b.y;
        if (a.z != b.z) return a.z < b.z;
        return a.index < b.index;
    });
    std::vector<uint32_t> remap(n);
    std::vector<glm::dvec3> merged;
    merged.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        if (i == 0 || !keys[i].samePlace(keys[i - 1]))
            merged.emplace_back(keys[i].x, keys[i].y, keys[i].z);
        remap[keys[i].index] = uint32_t(merged.size() - 1);
    }
    for (auto& t : mesh.triangles) {
        for (auto& v : t) v = remap[v];
    }
    const size_t removed = n - merged.size();
    mesh.vertices = std::move(merged);
    return removed;
}

MeshReport checkMesh(Mesh& mesh, const std::string& name, const MeshCheckOptions& options) {
    MeshReport report;
    report.file = name;
    report.trianglesIn = mesh.triangles.size();
    report.verticesIn = mesh.vertices.size();
    auto finish = [&]() -> MeshReport& {
        report.bounds = mesh.bounds();
        report.area = mesh.area();
        if (!report.problems.empty() && options.throwOnProblem)
            throw InputError(report.problems.front(), name);
        return report;
    };
    if (mesh.triangles.empty()) {
        report.problems.push_back("mesh has no triangles");
        return finish();
    }
    for (const auto& v : mesh.vertices) {
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
            report.problems.push_back("non-finite vertex coordinate " + formatPoint(v));
            return finish();
        }
    }
    // STL repeats every vertex in each triangle using it: merging is normal, not a repair.
    report.duplicateVerticesMerged = mergeDuplicateVertices(mesh);
    logDebug(name + ": merged " + std::to_string(report.duplicateVerticesMerged) +
             " duplicate vertices");

    dropDegenerateTriangles(mesh, report, options.repair);
    if (!report.problems.empty()) return finish();
    if (mesh.triangles.empty()) {
        report.problems.push_back("every triangle is degenerate");
        return finish();
    }
    std::vector<std::array<int64_t, 3>> neighbours;
    std::vector<std::array<bool, 3>> sameDirection;
    checkEdges(mesh, report, neighbours, sameDirection);
    if (!report.problems.empty()) return finish();

    std::vector<char> flip;
    std::vector<Shell> shells = orientShells(mesh, neighbours, sameDirection, flip, report);
    if (!report.problems.empty()) return finish();
    report.shells = shells.size();
    for (auto& shell : shells) {
        for (uint32_t t : shell.triangles) {
            for (uint32_t v : mesh.triangles[t]) shell.bounds.add(mesh.vertices[v]);
        }
        shell.volume = shellVolume(mesh, shell, flip);
    }
    for (const auto& shell : shells) {
        // A flat shell's volume is round-off, at most ~1e-16 x area x diagonal (the sum of triple
        // products about the centre). Compare with that, not with diagonal^3, which calls a
        // 1 x 1 x 1e6 mm column flat.
        const double diagonal = glm::length(shell.bounds.size());
        double area = 0.0;
        for (uint32_t t : shell.triangles) area += 0.5 * glm::length(mesh.triangleNormal(t));
        if (!(std::abs(shell.volume) > 1e-9 * area * diagonal)) {
            report.problems.push_back("mesh encloses no volume (a shell of " +
                                      std::to_string(shell.triangles.size()) + " triangles near " +
                                      formatPoint(shell.bounds.lo) + " is flat)");
            return finish();
        }
    }
    computeDepths(mesh, shells);

    size_t reoriented = 0;
    for (const auto& shell : shells) {
        // Outer shells enclose positive volume; cavities (odd depth) negative.
        const bool wantPositive = shell.depth % 2 == 0;
        const bool invert = (shell.volume > 0.0) != wantPositive;
        size_t changed = 0;
        for (uint32_t t : shell.triangles) {
            flip[t] = char(flip[t] ^ char(invert));
            changed += flip[t] ? 1 : 0;
        }
        if (changed == shell.triangles.size()) {
            ++report.shellsFlipped;
        } else {
            reoriented += changed;
        }
    }
    if (!options.repair && (reoriented > 0 || report.shellsFlipped > 0)) {
        if (reoriented > 0)
            report.problems.push_back(std::to_string(reoriented) +
                                      " triangles with inconsistent orientation");
        if (report.shellsFlipped > 0)
            report.problems.push_back("mesh is inside-out (negative volume)");
        return finish();
    }
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        if (flip[t]) std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
    }
    report.trianglesReoriented = reoriented;
    if (reoriented > 0) {
        addRepair(report, "reoriented " + std::to_string(reoriented) +
                              " triangles to agree with their neighbours (flood fill)");
    }
    if (report.shellsFlipped > 0) {
        addRepair(
            report,
            "turned " + std::to_string(report.shellsFlipped) +
                " shell(s) around (an outer shell had inward normals, or a cavity outward ones)");
    }
    report.volume = mesh.volume();
    return finish();
}

nlohmann::json MeshReport::toJson() const {
    nlohmann::json j;
    j["file"] = file;
    j["ok"] = ok();
    j["triangles_in"] = trianglesIn;
    j["vertices_in"] = verticesIn;
    j["duplicate_vertices_merged"] = duplicateVerticesMerged;
    j["degenerate_triangles_dropped"] = degenerateTrianglesDropped;
    j["sliver_triangles_kept"] = sliverTrianglesKept;
    j["triangles_reoriented"] = trianglesReoriented;
    j["shells_flipped"] = shellsFlipped;
    j["open_edges"] = openEdges;
    j["non_manifold_edges"] = nonManifoldEdges;
    j["shells"] = shells;
    j["volume_mm3"] = volume;
    j["area_mm2"] = area;
    if (!bounds.empty()) {
        j["bounds_mm"] = {{bounds.lo.x, bounds.lo.y, bounds.lo.z},
                          {bounds.hi.x, bounds.hi.y, bounds.hi.z}};
    }
    j["repairs"] = repairs;
    j["problems"] = problems;
    return j;
}

}  // namespace vpsim::geometry
