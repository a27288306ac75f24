#pragma once
/// @file
/// Exact signed distance from points to a closed triangle mesh through a bounding-volume
/// hierarchy: the nearest point on the nearest triangle, signed by the angle-weighted pseudonormal
/// of the face, edge or vertex it lies on (Baerentzen and Aanaes 2005), so the sign is right at
/// edges and corners of a closed, consistently oriented mesh. Costs O(log triangles) per query and
/// nothing per voxel: validation measures the cured surface where it is, without a 3D reference
/// grid.

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "vpsim/geometry/mesh.h"

namespace vpsim::geometry {

class MeshDistance {
public:
    /// @throw InputError when the mesh has no triangles
    explicit MeshDistance(const Mesh& mesh);
    /// Signed distance (mm): positive outside the mesh, negative inside. Thread-safe.
    double signedDistance(const glm::dvec3& p) const;
    static constexpr uint32_t NO_HINT = UINT32_MAX;
    /// The same for a run of nearby points (a row of the cured surface's vertices): `hint` is
    /// the nearest triangle of the previous point (NO_HINT at first) and becomes this one's.
    /// Ties between equally near triangles may resolve to another of them; the distance is the
    /// same.
    double signedDistance(const glm::dvec3& p, uint32_t& hint) const;

    /// Proofs that a triangle is the nearest one, kept for the points near where they were made
    /// (distance is 1-Lipschitz: if every triangle but t is at least `others` from `at`, every
    /// one is at least others - s from a point s away, so t is that point's nearest triangle
    /// wherever it is nearer than that, and no search is needed). The latest few, most recent
    /// first: a thread's rows of cured-surface vertices visit a few walls in turn. They belong
    /// to the MeshDistance that made them; one set per thread.
    struct NearestProofs {
        struct Proof {
            glm::dvec3 at{0.0};
            uint32_t slot = NO_HINT;
            double others = 0;
        };
        std::array<Proof, 4> recent;
        /// Searches since a proof last spared one: where proofs do not last (small facets of a
        /// curved part), a search proves its triangle only now and then (a proof costs a second
        /// search).
        uint32_t searchesSinceUse = 0;
        uint64_t searches = 0;  ///< queries that needed a search
    };
    /// signedDistance(p, hint), the same to the bit, without a search where one of `proofs`
    /// holds at p; a search adds a proof for p.
    double signedDistance(const glm::dvec3& p, uint32_t& hint, NearestProofs& proofs) const;

private:
    struct Node {
        glm::dvec3 lo, hi;
        uint32_t first = 0, count = 0;  ///< leaf: triangles [first, first + count)
        uint32_t left = 0, right = 0;   ///< inner node: children (count == 0)
    };
    uint32_t build(uint32_t first, uint32_t count);
    /// Calls visit(slot) for the triangles of the leaves whose boxes are nearer to p than
    /// `bound` (squared, which the visitor may lower as it goes), nearer boxes first.
    template <class Visit>
    void search(const glm::dvec3& p, const double& bound, Visit&& visit) const;
    /// The pseudonormal of triangle `slot`'s closest feature (closestOnTriangle's numbering).
    const glm::dvec3& normalAt(uint32_t slot, int feature) const;
    /// Distance from p to the nearest triangle other than `slot` (1e300 when there is none).
    double othersDistance(const glm::dvec3& p, uint32_t slot) const;
    std::vector<Node> mNodes;
    std::vector<std::array<glm::dvec3, 3>> mCorners;       ///< per triangle, in BVH order
    std::vector<glm::dvec3> mFaceNormal;                   ///< unit face normals
    std::vector<std::array<glm::dvec3, 3>> mEdgeNormal;    ///< edges ab, bc, ca (sums)
    std::vector<std::array<glm::dvec3, 3>> mVertexNormal;  ///< angle-weighted at a, b, c
    std::vector<std::array<glm::dvec3, 2>> mTriangleBox;   ///< bounds of each triangle
    std::vector<glm::dvec3> mCentroid, mBoxLo, mBoxHi;     ///< per triangle, while building
    std::vector<uint32_t> mOrder;
};

}  // namespace vpsim::geometry
