#include "vpsim/exposure/dose_volume.h"

#include <algorithm>
#include <climits>
#include <cmath>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/VolumeToMesh.h>

#include "core/vdb_file.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

namespace vpsim::exposure {

// Slices arrive one at a time (top down). They are buffered in blocks of 8 z-slices aligned
// with OpenVDB's 8^3 leaves, so each leaf is built once, in parallel, without merging.
constexpr int BLOCK = 8;

struct DoseVolume::Impl {
    openvdb::FloatGrid::Ptr grid;
    double voxelHeight, zBottom;
    float threshold;
    int nx = 0, ny = 0;
    CellWindow core;            ///< the cells buffered (a tile's core, or the whole grid)
    int block = INT32_MIN;      ///< index (k / 8) of the buffered block
    std::vector<float> buffer;  ///< core cells * 8 values, x fastest, then y, then z
    bool dirty = false;

    void flush() {
        if (!dirty) return;
        openvdb::CoordBBox box(openvdb::Coord(core.i0, core.j0, block * BLOCK),
                               openvdb::Coord(core.i1 - 1, core.j1 - 1, block * BLOCK + BLOCK - 1));
        openvdb::tools::Dense<const float, openvdb::tools::LayoutXYZ> dense(box, buffer.data());
        openvdb::tools::copyFromDense(dense, *grid, threshold);
        std::fill(buffer.begin(), buffer.end(), 0.0f);
        dirty = false;
    }
};

DoseVolume::DoseVolume(const ExposureGrid& grid, double voxelHeight, double zBottom,
                       float threshold, const std::string& name)
    : mImpl(std::make_unique<Impl>()) {
    vdb::initialise();
    mImpl->grid = openvdb::FloatGrid::create(0.0f);
    mImpl->grid->setName(name);
    mImpl->grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    // Voxel (i, j, k) is the cell whose corner is origin + (i*pitch, j*pitch, zBottom + k*h):
    // an affine map with unequal scales in x-y and z.
    openvdb::math::Mat4d matrix = openvdb::math::Mat4d::identity();
    matrix.preScale(openvdb::Vec3d(grid.pitch, grid.pitch, voxelHeight));
    matrix.postTranslate(openvdb::Vec3d(grid.originX + 0.5 * grid.pitch,
                                        grid.originY + 0.5 * grid.pitch,
                                        zBottom + 0.5 * voxelHeight));
    mImpl->grid->setTransform(openvdb::math::Transform::createLinearTransform(matrix));
    mImpl->grid->insertMeta("units", openvdb::StringMetadata("mJ/mm^2, world coordinates in mm"));
    mImpl->nx = grid.nx;
    mImpl->ny = grid.ny;
    mImpl->voxelHeight = voxelHeight;
    mImpl->zBottom = zBottom;
    mImpl->threshold = threshold;
}

DoseVolume::~DoseVolume() = default;

void DoseVolume::add(const ExposureSlice& slice) {
    const SurfaceGrid& values = *slice.values;
    Impl& m = *mImpl;
    const CellWindow core = slice.owned();
    if (core.i0 < values.firstI || core.j0 < values.firstJ || core.i1 > values.firstI + values.nx ||
        core.j1 > values.firstJ + values.ny || core.i1 > m.nx || core.j1 > m.ny)
        throw ResourceError("exposure slice does not match the dose volume");
    int k = int(std::lround((slice.z - m.zBottom) / m.voxelHeight - 0.5));
    int block = k >= 0 ? k / BLOCK : -((-k + BLOCK - 1) / BLOCK);
    const bool newCore = core.i0 != m.core.i0 || core.j0 != m.core.j0 || core.i1 != m.core.i1 ||
                         core.j1 != m.core.j1;
    if (block != m.block || newCore) {
        m.flush();
        m.block = block;
    }
    if (newCore) {  // a tile's core: its cells only, so each voxel is stored once
        m.core = core;
        m.buffer.assign(size_t(core.width()) * core.height() * BLOCK, 0.0f);
    }
    // Values within `threshold` of the background 0 stay inactive when the block is copied.
    float* target = m.buffer.data() + size_t(k - block * BLOCK) * core.width() * core.height();
    for (int j = core.j0; j < core.j1; ++j) {
        const float* row =
            &values.values[size_t(j - values.firstJ) * values.nx + size_t(core.i0 - values.firstI)];
        target = std::copy(row, row + core.width(), target);
    }
    m.dirty = true;
}

void DoseVolume::write(const std::string& path) const {
    mImpl->flush();
    vdb::writeGrids(path, {mImpl->grid});
}

uint64_t DoseVolume::activeVoxels() const {
    mImpl->flush();
    return mImpl->grid->activeVoxelCount();
}

float DoseVolume::maxValue() const {
    mImpl->flush();
    float hi = 0.0f;
    for (auto it = mImpl->grid->cbeginValueOn(); it; ++it) hi = std::max(hi, *it);
    return hi;
}

float DoseVolume::value(int i, int j, int k) const {
    mImpl->flush();
    return mImpl->grid->getConstAccessor().getValue(openvdb::Coord(i, j, k));
}

geometry::Mesh DoseVolume::isosurface(float isoValue) const {
    mImpl->flush();
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*mImpl->grid, points, triangles, quads, double(isoValue));
    geometry::Mesh mesh;
    mesh.vertices.reserve(points.size());
    for (const auto& p : points) mesh.vertices.emplace_back(p.x(), p.y(), p.z());
    // volumeToMesh orients faces for level sets (inside = below the iso-value); the cured
    // region is above it, so every face is reversed to point out of the cured part.
    for (const auto& t : triangles) mesh.triangles.push_back({t[2], t[1], t[0]});
    for (const auto& q : quads) {
        mesh.triangles.push_back({q[2], q[1], q[0]});
        mesh.triangles.push_back({q[3], q[2], q[0]});
    }
    return mesh;
}

uint64_t DoseVolume::memoryBytes() const {
    mImpl->flush();
    return mImpl->grid->memUsage();
}

}  // namespace vpsim::exposure
