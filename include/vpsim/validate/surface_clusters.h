#pragma once
/// @file
/// Vertex clustering of a surface (Rossignac and Borrel): the vertices in one cell of a grid of
/// `cell` mm merge into their mean (a value per vertex, averaged with them), and the triangles
/// whose corners fall in fewer than three cells vanish. Vertices and triangles are added one by
/// one, so a mesher can keep a picture of a surface far larger than memory: its size follows the
/// surface's area over cell^2 (about 2 A / cell^2 triangles), not the surface's own triangles.
///
/// Tiles: the owned vertices of a tile are summed apart, from zero, and added to the clusters'
/// sums when the tile ends (endTile), so that a tile clustered alone (an MPI rank's) and merged
/// in the tiles' order (merge) gives the one process's sums to the bit.

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

#include "vpsim/core/binary_state.h"
#include "vpsim/geometry/mesh.h"

namespace vpsim::validate {

class SurfaceClusters {
public:
    /// @throw InputError unless cell > 0
    explicit SurfaceClusters(double cell);
    /// The cluster of the vertex at `p`, made when it is the first in its cell. An `owned` vertex
    /// adds to the cluster's mean; one that is not (a copy of a vertex added elsewhere, as the
    /// halo of a tile repeats its neighbour's) only finds its cluster.
    uint32_t add(const glm::dvec3& p, float value, bool owned = true);
    /// Keeps the triangle of three clusters unless two are the same.
    void addTriangle(uint32_t a, uint32_t b, uint32_t c);
    /// Adds the tile's sums to the clusters' (before mesh, values, save or merge).
    void endTile();
    /// Appends a picture made alone of later tiles (ended, as `in` under `prefix` holds it, the
    /// records save writes): its clusters join this one's of the same cell (a new cell's come
    /// after this one's, in their order), its triangles follow. @throw InputError as restore's
    void merge(const BinaryStateReader& in, const std::string& prefix);
    double cell() const { return mCell; }
    size_t triangles() const { return mTriangles.size(); }
    /// The clustered mesh (mean positions, mm) and each vertex's mean value.
    geometry::Mesh mesh() const;
    std::vector<float> values() const;
    /// Checkpoints (a long tiled run's picture): the clusters and triangles as records named
    /// `prefix`.*; restore rebuilds the index from each cluster's first position (the cell it was
    /// made for). @throw InputError naming the state file when it is malformed or of another cell
    void save(BinaryStateWriter& out, const std::string& prefix) const;
    void restore(const BinaryStateReader& in, const std::string& prefix);

private:
    struct Key {
        int64_t x, y, z;
        bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct KeyHash {
        size_t operator()(const Key& k) const;
    };
    struct Cluster {
        glm::dvec3 sum{0.0}, first{0.0};  ///< owned positions' sum; the first position seen
        double valueSum = 0;
        uint32_t count = 0;
    };
    /// An owned vertex's share of the sums, summed apart per tile (endTile).
    struct TileSum {
        glm::dvec3 sum{0.0};
        double valueSum = 0;
        uint32_t count = 0;
    };
    Key keyOf(const glm::dvec3& p) const;  ///< the cell holding p
    /// The records `prefix`.* of `in`, checked as restore checks them.
    static void readChecked(const BinaryStateReader& in, const std::string& prefix, double cell,
                            std::vector<Cluster>& clusters,
                            std::vector<std::array<uint32_t, 3>>& triangles);
    /// The cluster of cell `key` (made at `first` when there is none): its index.
    uint32_t find(const Key& key, const glm::dvec3& first);
    double mCell;
    std::unordered_map<Key, uint32_t, KeyHash> mIndex;
    std::vector<Cluster> mClusters;
    std::vector<TileSum> mTile;      ///< per cluster, this tile's owned vertices
    std::vector<uint32_t> mTouched;  ///< the clusters with owned vertices in this tile
    std::vector<std::array<uint32_t, 3>> mTriangles;
    Key mLastKey{0, 0, 0};  ///< neighbouring vertices often share a cell: the last one found
    uint32_t mLast = UINT32_MAX;
};

}  // namespace vpsim::validate
