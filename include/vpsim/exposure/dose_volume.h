#pragma once
/// @file
/// Sparse 3D storage of exposure slices in an OpenVDB FloatGrid (OpenVDB stays out of this header).

#include <memory>
#include <string>

#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/geometry/mesh.h"

namespace vpsim::exposure {

/// Collects exposure slices as an OpenVDB float grid with voxel size (pitch, pitch, h/slices).
/// Values below `threshold` (mJ/mm^2) are left as background 0, so storage follows the exposed
/// region.
class DoseVolume {
public:
    /// @param name grid name in the .vdb ("exposure")
    DoseVolume(const ExposureGrid& grid, double voxelHeight, double zBottom, float threshold,
               const std::string& name = "exposure");
    ~DoseVolume();
    /// A SliceSink adding each slice at its voxel index k = round((z - zBottom)/voxelHeight - 0.5).
    /// Slices are buffered by blocks of 8 in z; they should arrive block by block (as the engine's
    /// top-down order does): a slice for an already flushed block is merged, more slowly.
    void add(const ExposureSlice& slice);
    /// Writes the grid as .vdb (atomic). @throw InputError when the file cannot be written
    void write(const std::string& path) const;
    /// Stored (active) voxels.
    uint64_t activeVoxels() const;
    /// Largest stored value.
    float maxValue() const;
    /// Value at voxel (i, j, k) (background 0 when not stored).
    float value(int i, int j, int k) const;
    /// The iso-surface where the exposure equals `isoValue` (the cured part's surface at the
    /// critical dose), triangulated with outward normals, in mm (OpenVDB volumeToMesh).
    geometry::Mesh isosurface(float isoValue) const;
    /// Memory used by the grid, bytes.
    uint64_t memoryBytes() const;

    struct Impl;
    Impl& impl() const { return *mImpl; }

private:
    std::unique_ptr<Impl> mImpl;
};

}  // namespace vpsim::exposure
