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
/// the threads.

#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/mesh.h"

namespace vpsim::validate {

class StreamingCuredSurface {
public:
    /// @param isoValue the critical dose (mJ/mm^2): cured where exposure >= isoValue
    /// @param part the reference model (signed deviations of the vertices), or nullptr for none
    /// @param band deviations are clamped to +-band (mm), as the reference level set's band was
    /// @param stlPath binary STL written atomically at finish(), or "" for none
    StreamingCuredSurface(const exposure::ExposureGrid& grid, double voxelHeight, double isoValue,
                          const geometry::Mesh* part, double band, const std::string& stlPath);
    ~StreamingCuredSurface();
    /// A SliceSink: slices one voxel height apart, from the top down.
    void add(const exposure::ExposureSlice& slice);
    /// Closes the bottom and the STL. @throw InputError when nothing cured
    void finish();

    uint64_t triangles() const;
    /// Enclosed volume (mm^3), by the divergence theorem over the triangles.
    double volume() const;
    /// Vertex positions (mm) in the order made, and their signed deviations from the part (mm).
    const std::vector<glm::vec3>& vertices() const;
    const std::vector<float>& deviations() const;
    /// The whole mesh, for tests and small runs (vertices as made, triangles as written).
    geometry::Mesh mesh() const;
    /// Keep the triangles in memory for mesh() (off by default: they stream to the STL).
    void keepTriangles(bool keep);

private:
    struct State;
    std::unique_ptr<State> mState;
};

}  // namespace vpsim::validate
