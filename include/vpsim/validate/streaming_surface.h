#pragma once
/// @file
/// The cured surface, meshed while the exposure engine emits its slices (a SliceSink): naive
/// surface nets over a sliding window of two slices (one vertex per cube that the iso-surface
/// crosses, at the mean of its edge crossings; one quad per crossed grid edge, joining the four
/// cubes around it), so no 3D dose grid is stored. Each vertex exists once (shared by the quads of
/// its cube), and the domain is padded with zero exposure on every side, so the mesh is closed.
/// Triangles go to a binary STL as they are produced; each vertex's signed distance from the part
/// (exact, through geometry::MeshDistance) is taken when the vertex is made. The work of a slice
/// is split over grid rows and put back together in row order, so the output does not depend on
/// the threads. add() copies its slice and returns, making the layer of cubes in the background
/// while the engine makes the next slice; every other call waits for that layer first.

#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include "vpsim/core/binary_state.h"
#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/mesh.h"
#include "vpsim/validate/surface_deviation.h"

namespace vpsim::validate {

class StreamingCuredSurface {
public:
    /// @param isoValue the critical dose (mJ/mm^2): cured where exposure >= isoValue
    /// @param part the reference model (signed deviations of the vertices), or nullptr for none
    /// @param band deviations are clamped to +-band (mm), as the reference level set's band was
    /// @param stlPath binary STL written atomically at finish(), or "" for none
    StreamingCuredSurface(const exposure::ExposureGrid& grid, double voxelHeight, double isoValue,
                          const geometry::Mesh* part, double band, const std::string& stlPath);
    /// A binary STL written in place at `path` (not through a temporary), so that a run can
    /// resume it after a kill (saveState / restoreState); the caller moves it into place.
    struct InPlaceStl {
        std::string path;
    };
    StreamingCuredSurface(const exposure::ExposureGrid& grid, double voxelHeight, double isoValue,
                          const geometry::Mesh* part, double band, InPlaceStl stl);
    ~StreamingCuredSurface();
    /// A SliceSink: slices one voxel height apart, from the top down. The slice may be reused
    /// as soon as this returns; an error of the layer made in the background is thrown by the
    /// next call.
    void add(const exposure::ExposureSlice& slice);
    /// Closes the bottom and the STL. @throw InputError when nothing cured
    void finish();

    uint64_t triangles() const;
    /// Enclosed volume (mm^3), by the divergence theorem over the triangles.
    double volume() const;
    /// Vertex positions (mm) in the order made, and their signed deviations from the part (mm):
    /// all of them with keepTriangles(true), else only the last layer's until finish() and none
    /// after (memory follows the tile, not the surface; the statistics have them all).
    const std::vector<glm::vec3>& vertices() const;
    const std::vector<float>& deviations() const;
    /// Running statistics of every vertex's deviation, tile by tile merged in the tiles' order
    /// (complete after finish()).
    const DeviationStatistics& statistics() const;
    /// The whole mesh, for tests and small runs (vertices as made, triangles as written).
    geometry::Mesh mesh() const;
    /// Keep the triangles in memory for mesh() (off by default: they stream to the STL).
    void keepTriangles(bool keep);
    /// Keep a picture of the surface for the report (before the first slice): its vertices
    /// merged on a grid of `cell` mm as they are made (SurfaceClusters), so memory follows the
    /// picture, not the surface; cell 0 keeps every triangle (keepTriangles).
    void keepView(double cell);
    /// The kept picture: the mesh and each vertex's (mean) deviation from the part, mm.
    struct View {
        geometry::Mesh mesh;
        std::vector<float> deviations;
        double cell = 0;         ///< the clustering cell, mm; 0: every triangle as made
        uint64_t madeTriangles;  ///< the cured surface's own triangles (cured.stl's)
    };
    View view() const;

    /// Between two tiles (after a tile's last slice), with an in-place STL or none: closes the
    /// tile and returns what the next tiles build on (counts, volume, statistics, the STL's
    /// length, flushed); the kept picture goes apart (savePicture). @throw InputError otherwise
    nlohmann::json saveState();
    /// After saveState: the kept picture (keepView), as records named "cured.*": the clusters, or
    /// the triangles kept with their vertices. restorePicture, after restoreState, continues it.
    /// @throw InputError naming the state file when it is malformed or of another view
    void savePicture(BinaryStateWriter& out) const;
    void restorePicture(const BinaryStateReader& in);
    /// Before the first slice: continues from a saved state, cutting the in-place STL back to
    /// its saved length. @throw InputError for a malformed state or a shorter STL
    void restoreState(const nlohmann::json& state);
    /// Appends the tiles another surface made (its saveState), as if this one had made them
    /// next: the tiles of a job made on other MPI ranks, merged in the tiles' order. Their
    /// triangles follow through appendStl. @throw InputError for a malformed state
    void mergeState(const nlohmann::json& later);
    /// After mergeState: the next bytes of the merged tiles' STL triangles (their STL after its
    /// 84-byte header), in pieces in order; nothing when this surface writes no STL.
    void appendStl(const std::string& triangles);
    /// With mergeState: appends the kept picture of those tiles (its savePicture), as if this
    /// surface had made them next: the same clusters and sums, or the same kept triangles, to the
    /// bit. @throw InputError naming the state file when it is malformed or of another view
    void mergePicture(const BinaryStateReader& later);

private:
    struct State;
    std::unique_ptr<State> mState;
};

}  // namespace vpsim::validate
