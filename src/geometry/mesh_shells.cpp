// Connected shells of a triangle mesh (the topology half of mesh_check.cpp): a consistent
// orientation per shell by flood fill, signed volumes, and nesting depth by ray parity.

#include "mesh_shells.h"

#include <cmath>
#include <sstream>

#include <glm/geometric.hpp>

namespace vpsim::geometry::detail {
namespace {

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

bool boundsInside(const Bounds& inner, const Bounds& outer) {
    return glm::all(glm::greaterThanEqual(inner.lo, outer.lo)) &&
           glm::all(glm::lessThanEqual(inner.hi, outer.hi));
}

}  // namespace

std::string formatPoint(const glm::dvec3& p) {
    std::ostringstream s;
    s.precision(6);
    s << "(" << p.x << ", " << p.y << ", " << p.z << ") mm";
    return s.str();
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

}  // namespace vpsim::geometry::detail
