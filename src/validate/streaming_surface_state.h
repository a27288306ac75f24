#pragma once
// Private to src/validate: the state of StreamingCuredSurface (streaming_surface.cpp: the public
// calls; streaming_surface_layers.cpp: meshing a layer of cubes between two slices and writing
// its triangles; streaming_surface_tiles.cpp: a tile's working memory, started, trimmed and
// released; streaming_surface_state.cpp: the checkpoint state).

#include <array>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_group.h>
#include <glm/vec3.hpp>

#include "vpsim/core/io.h"
#include "vpsim/geometry/mesh_distance.h"
#include "vpsim/validate/streaming_surface.h"
#include "vpsim/validate/surface_clusters.h"

namespace vpsim::validate {
namespace surface_detail {

inline void writeStlHeader(std::ostream& out) {
    char header[84] = {};
    const std::string text = "vpsim binary STL, mm: cured";
    std::memcpy(header, text.data(), text.size());
    out.write(header, 84);
}

constexpr uint32_t NONE = UINT32_MAX;
constexpr uint32_t HALO = 0x80000000u;  ///< a vertex index into the halo's vertices

/// A slice padded with one zero cell on every side: (nx + 2) x (ny + 2) values and cured flags.
struct PaddedSlice {
    std::vector<float> value;
    std::vector<uint8_t> in;
    double z = 0;
};

inline uint64_t load8(const uint8_t* p) {
    uint64_t word;
    std::memcpy(&word, p, 8);
    return word;
}

/// mask[i] != 0 where cube i between rows j, j + 1 of the slices above (a0, a1) and below (b0,
/// b1) has corners inside and outside (0/1 flags), for `cubes` cubes: one pass over the rows
/// that the compiler vectorises, then the few such cubes are found eight at a time.
void mixedCubes(const uint8_t* a0, const uint8_t* a1, const uint8_t* b0, const uint8_t* b1,
                uint8_t* mask, int cubes);

/// mask[i] != 0 where sample i of `above` has a crossing z, x or y edge (row width W), for
/// `samples` samples.
void crossingEdges(const uint8_t* above, const uint8_t* below, int width, uint8_t* mask,
                   int samples);

}  // namespace surface_detail

struct StreamingCuredSurface::State {
    exposure::ExposureGrid grid;
    double voxelHeight, iso, band;
    float curedAt = 0;  ///< v >= curedAt exactly when double(v) >= iso (CureLaw::floatAtLeast)
    std::unique_ptr<geometry::MeshDistance> distance;
    /// Each thread's latest proofs of nearest triangles (MeshDistance::NearestProofs): most
    /// vertices need no search. They change no result, so which thread has which does not matter.
    tbb::enumerable_thread_specific<geometry::MeshDistance::NearestProofs> nearestProofs;
    std::unique_ptr<AtomicFileStream> stl;
    /// The STL written in place (resumable: it survives a kill), opened at the first slice or
    /// by restoreState.
    std::string inPlacePath;
    std::unique_ptr<std::fstream> inPlace;
    std::ostream* stlOut = nullptr;  ///< the STL's stream, or none
    int nx, ny, P, Q;                ///< whole grid's cells; its padded width and height
    // The current tile, in padded samples of the whole grid: it owns the samples (and the edges
    // and cubes that start there) in [own.i0, own.i1) x [own.j0, own.j1) and holds the samples
    // in [sx0, sx0 + W) x [sy0, sy0 + H): one more on each side, for the cubes its edges join.
    exposure::CellWindow core{0, 0, -1, -1}, own;
    int sx0 = 0, sy0 = 0, W = 0, H = 0;
    int step = 0;  ///< cube layers made in this tile (every tile makes the same layers)
    surface_detail::PaddedSlice above, below;
    bool started = false, finished = false, referenceSet = false;
    std::vector<uint32_t> layerAbove, layerBelow;  ///< vertex per cube, (W - 1) x (H - 1)
    /// The cubes given a vertex in layerAbove and layerBelow: only those are cleared for the
    /// next layer (the whole layer would be 4 bytes a cell per slice).
    std::vector<uint32_t> filledAbove, filledBelow;
    /// Vertices of the cubes the tiles own and their deviations: all of them when the
    /// triangles are kept, else from the layer above on (trimVertices), vertices[0] being the
    /// run's vertex number `base`: memory follows a layer of the tile, not the surface.
    std::vector<glm::vec3> vertices;
    std::vector<float> deviations;
    uint64_t base = 0, layerStart = 0;  ///< numbers of vertices[0] and of the layer above's first
    /// Deviations of this tile (in the order made) and of the finished tiles (merged in order).
    DeviationStatistics tileStatistics, statistics;
    /// Cubes beside the tile that another tile owns: their vertices are made again (from the
    /// same values, so at the same positions) and referred to as HALO | index.
    std::vector<glm::vec3> haloVertices;
    std::vector<uint64_t> haloKeys;  ///< cube keys of haloVertices (when triangles are kept)
    size_t haloAbove = 0;            ///< haloVertices before the layer above's
    std::unordered_map<uint64_t, uint32_t> seamVertices;  ///< owned cubes a neighbour makes too
    std::vector<std::vector<std::pair<int, glm::vec3>>> rowVertices;
    std::vector<std::vector<std::array<uint32_t, 3>>> rowTriangles;
    std::vector<double> rowVolume;
    std::vector<std::array<uint32_t, 3>> kept;
    bool keep = false;
    /// The report's clustered picture of the surface (keepClusteredView), and the cluster of
    /// each vertex in `vertices` and `haloVertices`.
    std::unique_ptr<SurfaceClusters> clusters;
    std::vector<uint32_t> vertexCluster, haloCluster;
    uint64_t triangleCount = 0;
    double volume = 0, tileVolume = 0;  ///< the finished tiles', and this tile's (merged in order)
    glm::dvec3 reference{0.0};  ///< volume moments are taken about this point (less rounding)
    static constexpr size_t STL_GROUP = 1 << 11;  ///< triangles formatted at a time (or a row)
    static constexpr size_t STL_RECORD = 50;      ///< bytes of a binary STL triangle
    /// A group of rows' triangles as STL records, and where each row's begin (in triangles).
    std::vector<char> groupStl;
    std::vector<size_t> groupOffsets;

    /// After the last tile: frees the slices, the layers' indices and the rows' buffers (a layer's
    /// worth of triangles at a flat face), and the vertices unless every one is kept, so that the
    /// report that follows does not hold them.
    void releaseWorkingMemory();

    size_t sample(int li, int lj) const { return size_t(lj) * W + li; }
    size_t cube(int li, int lj) const { return size_t(lj) * (W - 1) + li; }
    /// Position of the whole grid's padded sample (pi, pj).
    glm::dvec3 position(int pi, int pj, double z) const {
        return {grid.originX + (pi - 0.5) * grid.pitch, grid.originY + (pj - 0.5) * grid.pitch, z};
    }
    const glm::vec3& vertex(uint32_t index) const {
        return index & surface_detail::HALO ? haloVertices[index & ~surface_detail::HALO]
                                            : vertices[index];
    }
    uint32_t clusterOf(uint32_t index) const {
        return index & surface_detail::HALO ? haloCluster[index & ~surface_detail::HALO]
                                            : vertexCluster[index];
    }
    uint64_t cubeKey(int ci, int cj) const {
        return (uint64_t(step) * uint64_t(Q - 1) + uint64_t(cj)) * uint64_t(P - 1) + uint64_t(ci);
    }

    /// A fresh in-place STL, opened by the first tile made or merged (not by restoreState).
    void openInPlace();
    /// Starts the tile whose core cells are `w` (the whole grid when untiled).
    void startTile(const exposure::CellWindow& w);
    /// The tile's bottom: the zero padding below its last slice closes its part of the mesh.
    void closeTile();
    /// Without kept triangles, only the layer above's vertices are referred to again: drops the
    /// older ones (owned and halo) and renumbers layerAbove's references.
    void trimVertices();
    void load(surface_detail::PaddedSlice& target, const exposure::SurfaceGrid* values, double z);
    /// The vertex of local cube (li, lj) between `above` and `below`: the mean of its edge
    /// crossings.
    glm::dvec3 cubeVertex(int li, int lj) const;
    bool ownsCube(int ci, int cj) const;
    /// A layer's new vertices: owned [from, to) in `vertices`, halo [haloFrom, ...) in
    /// haloVertices.
    struct NewVertices {
        size_t from, to, haloFrom;
    };
    /// Vertices of the cubes between `above` and `below` into layerBelow, rows in parallel and
    /// numbered in row order.
    NewVertices buildLayer();
    /// The new vertices into the tile's statistics and the picture's clusters, in their order
    /// (so neither depends on the threads).
    void addVertices(const NewVertices& made);
    /// Quads of the z edges between `above` and `below` and of the x and y edges in the plane of
    /// `above` (its cubes above: layerAbove, below: layerBelow), each split in two triangles:
    /// those of the edges that start at a sample the tile owns. The layer's vertices are added
    /// (addVertices) beside the quads and their STL, before the triangles join the picture.
    void emitQuads(const NewVertices& made);
    /// emitQuads' quads: their triangles per row (rowTriangles), the volume's moments, the STL.
    void makeQuads();
    /// Counts a row's triangles and keeps them for the picture.
    void record(const std::vector<std::array<uint32_t, 3>>& triangles);
    /// The triangles as binary STL records (normal, corners, no attribute) from `records` on.
    void formatStl(const std::vector<std::array<uint32_t, 3>>& triangles, char* records) const;
    /// Copies the slice (`values`, none: zero exposure) under the layer above and makes the
    /// cubes between them: in the background when asked, so that the engine makes its next slice
    /// meanwhile (the copy is made first: the caller may reuse the slice on return).
    void advance(const exposure::SurfaceGrid* values, double z, bool inBackground = false);
    /// Waits for the layer made in the background, if any (rethrowing what it threw): every
    /// public call starts here, so none sees a half-made layer.
    void settle() const;
    mutable tbb::task_group layerWork;
    mutable bool layerPending = false;
};

}  // namespace vpsim::validate
