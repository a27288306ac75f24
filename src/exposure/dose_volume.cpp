#include "vpsim/exposure/dose_volume.h"

#include <cmath>

#include <openvdb/openvdb.h>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

namespace vpsim::exposure {

struct DoseVolume::Impl {
    openvdb::FloatGrid::Ptr grid;
    double voxelHeight, zBottom;
    float threshold;
};

DoseVolume::DoseVolume(const ExposureGrid& grid, double voxelHeight, double zBottom, float threshold,
                       const std::string& name)
    : mImpl(std::make_unique<Impl>()) {
    openvdb::initialize();
    mImpl->grid = openvdb::FloatGrid::create(0.0f);
    mImpl->grid->setName(name);
    mImpl->grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    // Voxel (i, j, k) is the cell whose corner is origin + (i*pitch, j*pitch, zBottom + k*h):
    // an affine map with unequal scales in x-y and z.
    openvdb::math::Mat4d matrix = openvdb::math::Mat4d::identity();
    matrix.preScale(openvdb::Vec3d(grid.pitch, grid.pitch, voxelHeight));
    matrix.postTranslate(openvdb::Vec3d(grid.originX + 0.5 * grid.pitch, grid.originY + 0.5 * grid.pitch,
                                        zBottom + 0.5 * voxelHeight));
    mImpl->grid->setTransform(openvdb::math::Transform::createLinearTransform(matrix));
    mImpl->grid->insertMeta("units", openvdb::StringMetadata("mJ/mm^2, world coordinates in mm"));
    mImpl->voxelHeight = voxelHeight;
    mImpl->zBottom = zBottom;
    mImpl->threshold = threshold;
}

DoseVolume::~DoseVolume() = default;

void DoseVolume::add(const ExposureSlice& slice) {
    const SurfaceGrid& values = *slice.values;
    int k = int(std::lround((slice.z - mImpl->zBottom) / mImpl->voxelHeight - 0.5));
    auto accessor = mImpl->grid->getAccessor();
    for (int j = 0; j < values.ny; ++j)
        for (int i = 0; i < values.nx; ++i) {
            float v = values.at(i, j);
            if (v >= mImpl->threshold) accessor.setValue(openvdb::Coord(i, j, k), v);
        }
}

void DoseVolume::write(const std::string& path) const {
    writePathAtomic(path, [&](const std::string& temporary) {
        try {
            openvdb::io::File file(temporary);
            file.write({mImpl->grid});
            file.close();
        } catch (const openvdb::Exception& e) {
            throw InputError(std::string("cannot write OpenVDB file: ") + e.what(), path);
        }
    });
}

uint64_t DoseVolume::activeVoxels() const { return mImpl->grid->activeVoxelCount(); }

float DoseVolume::maxValue() const {
    float hi = 0.0f;
    for (auto it = mImpl->grid->cbeginValueOn(); it; ++it) hi = std::max(hi, *it);
    return hi;
}

float DoseVolume::value(int i, int j, int k) const {
    return mImpl->grid->getConstAccessor().getValue(openvdb::Coord(i, j, k));
}

uint64_t DoseVolume::memoryBytes() const { return mImpl->grid->memUsage(); }

} // namespace vpsim::exposure
