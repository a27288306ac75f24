#include "vpsim/geometry/mesh_check.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tbb/parallel_sort.h>
#include <glm/geometric.hpp>

#include "mesh_shells.h"
#include "vpsim/core/error.h"
#include "vpsim/core/log.h"

namespace vpsim::geometry {
namespace {

using detail::computeDepths;
using detail::formatPoint;
using detail::orientShells;
using detail::Shell;
using detail::shellVolume;

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
