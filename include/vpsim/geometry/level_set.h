#pragma once
/// @file
/// The part's reference signed distance field (narrow-band level set) for validation, built
/// with OpenVDB (tools::meshToLevelSet) and saved as .vdb. OpenVDB stays out of this header
/// (pimpl): its headers cost 5-20 s per translation unit (docs/PLATFORM.md, "Build time").
///
/// Sign convention (OpenVDB's): negative inside the part, positive outside, in mm. Values are
/// exact Euclidean distances to the triangles within the band and +-halfWidth beyond it.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "vpsim/geometry/mesh.h"

namespace vpsim::geometry {

/// Options of LevelSet::fromMesh().
struct LevelSetOptions {
    double voxelSize = 0.02;               ///< mm (voxel centres at integer multiples of it)
    double halfWidthVoxels = 3.0;          ///< narrow band half-width in voxels (>= 1)
    double maxBytes = 8.0 * (1ull << 30);  ///< refuse grids whose estimated memory exceeds this
};

/// A narrow-band signed distance grid of a closed mesh.
class LevelSet {
public:
    /// Converts a closed mesh (mm). Memory is estimated from the surface area before building.
    /// @throw InputError on a non-positive voxel size or half-width, or an empty mesh
    /// @throw ResourceError when the estimate exceeds options.maxBytes (message gives both)
    static LevelSet fromMesh(const Mesh& mesh, const LevelSetOptions& options = {});
    /// Reads the first float grid of a .vdb file. @throw InputError naming the file
    static LevelSet load(const std::string& path);
    /// Estimated peak memory (bytes) of fromMesh() for this mesh and options.
    static double estimateBytes(const Mesh& mesh, const LevelSetOptions& options);

    LevelSet(LevelSet&&) noexcept;
    LevelSet& operator=(LevelSet&&) noexcept;
    ~LevelSet();

    /// Trilinearly interpolated signed distance at p (mm); +-halfWidth far from the surface.
    double signedDistance(const glm::dvec3& p) const;
    /// Samples many points at once (mm) into `out` (same length), in parallel; use this rather
    /// than signedDistance() in loops.
    void sample(const std::vector<glm::dvec3>& points, std::vector<float>& out) const;
    double voxelSize() const;  ///< mm
    double halfWidth() const;  ///< band half-width (mm), also the background value
    size_t activeVoxelCount() const;
    size_t memoryBytes() const;
    /// Bounding box of the active voxels (mm).
    Bounds activeBounds() const;
    /// Writes a .vdb file (grid name "part", atomic: temp file then rename).
    /// @throw InputError when the file cannot be written
    void save(const std::string& path) const;

private:
    struct Impl;
    explicit LevelSet(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> mImpl;
};

}  // namespace vpsim::geometry
