#include "vpsim/geometry/mesh_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "vpsim/core/error.h"

namespace vpsim::geometry {
namespace {

/// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5) and the
/// feature it lies on: 0 face, 1..3 edges ab, bc, ca, 4..6 vertices a, b, c.
glm::dvec3 closestOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                             const glm::dvec3& c, int& feature) {
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return feature = 4, a;
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return feature = 5, b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return feature = 1, a + ab * (d1 / (d1 - d3));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return feature = 6, c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return feature = 3, a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return feature = 2, b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double denom = 1.0 / (va + vb + vc);
    feature = 0;
    return a + ab * (vb * denom) + ac * (vc * denom);
}

double boxDistanceSquared(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 d = glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0));
    return glm::dot(d, d);
}

double angleAt(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 u = b - a, v = c - a;
    const double lu = glm::length(u), lv = glm::length(v);
    if (lu <= 0 || lv <= 0) return 0.0;
    return std::acos(std::clamp(glm::dot(u, v) / (lu * lv), -1.0, 1.0));
}

}  // namespace

MeshDistance::MeshDistance(const Mesh& mesh) {
    const size_t n = mesh.triangles.size();
    if (n == 0) throw InputError("distance to an empty mesh");
    // Pseudonormals: per face its unit normal; per edge the sum over its faces; per vertex the
    // angle-weighted sum over its faces.
    std::vector<glm::dvec3> face(n), vertex(mesh.vertices.size(), glm::dvec3(0.0));
    std::map<std::pair<uint32_t, uint32_t>, glm::dvec3> edge;
    for (size_t t = 0; t < n; ++t) {
        const glm::dvec3 normal = mesh.triangleNormal(t);
        const double length = glm::length(normal);
        face[t] = length > 0 ? normal / length : glm::dvec3(0.0);
        const auto& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
            vertex[a] += face[t] * angleAt(mesh.vertices[a], mesh.vertices[b], mesh.vertices[c]);
            edge[{std::min(a, b), std::max(a, b)}] += face[t];
        }
    }
    mOrder.resize(n);
    std::iota(mOrder.begin(), mOrder.end(), 0u);
    mCentroid.resize(n);
    mBoxLo.resize(n);
    mBoxHi.resize(n);
    for (size_t t = 0; t < n; ++t) {
        const auto& tri = mesh.triangles[t];
        const glm::dvec3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]],
                         &c = mesh.vertices[tri[2]];
        mCentroid[t] = (a + b + c) / 3.0;
        mBoxLo[t] = glm::min(a, glm::min(b, c));
        mBoxHi[t] = glm::max(a, glm::max(b, c));
    }
    mNodes.reserve(2 * n);
    mCorners.resize(n);
    build(0, uint32_t(n));
    mFaceNormal.resize(n);
    mEdgeNormal.resize(n);
    mVertexNormal.resize(n);
    mTriangleBox.resize(n);
    for (size_t s = 0; s < n; ++s) {
        const uint32_t t = mOrder[s];
        const auto& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            mCorners[s][k] = mesh.vertices[tri[k]];
            const uint32_t a = tri[k], b = tri[(k + 1) % 3];
            mEdgeNormal[s][k] = edge[{std::min(a, b), std::max(a, b)}];
            mVertexNormal[s][k] = vertex[a];
        }
        mFaceNormal[s] = face[t];
        mTriangleBox[s] = {mBoxLo[t], mBoxHi[t]};
    }
    mCentroid = {};
    mBoxLo = {};
    mBoxHi = {};
}

uint32_t MeshDistance::build(uint32_t first, uint32_t count) {
    const uint32_t index = uint32_t(mNodes.size());
    mNodes.emplace_back();
    Node node;
    node.lo = glm::dvec3(1e300);
    node.hi = glm::dvec3(-1e300);
    glm::dvec3 clo(1e300), chi(-1e300);
    for (uint32_t s = first; s < first + count; ++s) {
        const uint32_t t = mOrder[s];
        clo = glm::min(clo, mCentroid[t]);
        chi = glm::max(chi, mCentroid[t]);
        node.lo = glm::min(node.lo, mBoxLo[t]);
        node.hi = glm::max(node.hi, mBoxHi[t]);
    }
    if (count <= 4) {
        node.first = first;
        node.count = count;
    } else {
        const glm::dvec3 extent = chi - clo;
        const int splitAxis =
            extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        const uint32_t mid = first + count / 2;
        std::nth_element(mOrder.begin() + first, mOrder.begin() + mid,
                         mOrder.begin() + first + count, [&](uint32_t a, uint32_t b) {
                             return mCentroid[a][splitAxis] < mCentroid[b][splitAxis];
                         });
        node.left = build(first, mid - first);
        node.right = build(mid, first + count - mid);
    }
    mNodes[index] = node;
    return index;
}

template <class Visit>
void MeshDistance::search(const glm::dvec3& p, const double& bound, Visit&& visit) const {
    uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = mNodes[stack[--top]];
        if (boxDistanceSquared(p, node.lo, node.hi) >= bound) continue;
        if (node.count > 0) {
            for (uint32_t s = node.first; s < node.first + node.count; ++s) visit(s);
            continue;
        }
        const Node& l = mNodes[node.left];
        const Node& r = mNodes[node.right];
        const double dl = boxDistanceSquared(p, l.lo, l.hi), dr = boxDistanceSquared(p, r.lo, r.hi);
        if (dl < dr) {  // nearer child popped first
            stack[top++] = node.right;
            stack[top++] = node.left;
        } else {
            stack[top++] = node.left;
            stack[top++] = node.right;
        }
    }
}

const glm::dvec3& MeshDistance::normalAt(uint32_t slot, int feature) const {
    return feature == 0   ? mFaceNormal[slot]
           : feature <= 3 ? mEdgeNormal[slot][feature - 1]
                          : mVertexNormal[slot][feature - 4];
}

double MeshDistance::signedDistance(const glm::dvec3& p) const {
    uint32_t hint = NO_HINT;
    return signedDistance(p, hint);
}

double MeshDistance::signedDistance(const glm::dvec3& p, uint32_t& hint) const {
    double best = 1e300;
    glm::dvec3 bestPoint(0.0), bestNormal(0.0);
    uint32_t bestSlot = NO_HINT;
    auto visit = [&](uint32_t s) {
        // A triangle's own box is as far as the triangle at least: most fall behind the bound.
        if (boxDistanceSquared(p, mTriangleBox[s][0], mTriangleBox[s][1]) >= best) return;
        int feature = 0;
        const auto& c = mCorners[s];
        const glm::dvec3 q = closestOnTriangle(p, c[0], c[1], c[2], feature);
        const double d = glm::dot(p - q, p - q);
        if (d < best) {
            best = d;
            bestPoint = q;
            bestSlot = s;
            bestNormal = normalAt(s, feature);
        }
    };
    // A neighbouring query's nearest triangle is most often this one's too: its distance bounds
    // the search from the start, so the traversal skips most boxes.
    if (hint < mCorners.size()) visit(hint);
    search(p, best, [&](uint32_t s) {
        if (s != hint) visit(s);
    });
    hint = bestSlot;
    const double distance = std::sqrt(best);
    return glm::dot(p - bestPoint, bestNormal) < 0 ? -distance : distance;
}

double MeshDistance::othersDistance(const glm::dvec3& p, uint32_t slot) const {
    double best = std::numeric_limits<double>::infinity();  // squared
    search(p, best, [&](uint32_t s) {
        if (s == slot || boxDistanceSquared(p, mTriangleBox[s][0], mTriangleBox[s][1]) >= best)
            return;
        int feature = 0;
        const auto& c = mCorners[s];
        const glm::dvec3 q = closestOnTriangle(p, c[0], c[1], c[2], feature);
        best = std::min(best, glm::dot(p - q, p - q));
    });
    return std::min(std::sqrt(best), 1e300);
}

double MeshDistance::signedDistance(const glm::dvec3& p, uint32_t& hint,
                                    NearestProofs& proofs) const {
    auto& recent = proofs.recent;
    for (size_t k = 0; k < recent.size() && recent[k].slot != NO_HINT; ++k) {
        const NearestProofs::Proof& proof = recent[k];
        const double shift = glm::length(p - proof.at);
        if (shift >= proof.others) continue;
        int feature = 0;
        const auto& c = mCorners[proof.slot];
        const glm::dvec3 q = closestOnTriangle(p, c[0], c[1], c[2], feature);
        const double best = glm::dot(p - q, p - q);
        // Nearer by a margin far above rounding: the search too would find this triangle (and
        // only it) nearest, and return what follows, bit for bit.
        if (std::sqrt(best) + shift >= proof.others * (1 - 1e-9) - 1e-12) continue;
        hint = proof.slot;
        proofs.searchesSinceUse = 0;
        std::rotate(recent.begin(), recent.begin() + ptrdiff_t(k),
                    recent.begin() + ptrdiff_t(k) + 1);
        const double distance = std::sqrt(best);
        return glm::dot(p - q, normalAt(hint, feature)) < 0 ? -distance : distance;
    }
    const double distance = signedDistance(p, hint);
    ++proofs.searches;
    const uint32_t since = ++proofs.searchesSinceUse;
    if (since <= 4 || since % 16 == 0) {
        std::rotate(recent.begin(), recent.end() - 1, recent.end());  // the oldest goes
        recent[0] = {p, hint, othersDistance(p, hint)};
    }
    return distance;
}

}  // namespace vpsim::geometry
