// Saves a beam kernel as OpenVDB grids (OpenVDB headers only here).

#include <cmath>

#include <openvdb/openvdb.h>

#include "core/vdb_file.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/kernel/beam_kernel.h"

namespace vpsim::kernel {

namespace {

/// Largest Cartesian grid written (float voxels, before sparsity).
constexpr double MAX_VOXELS = 32.0 * 1024 * 1024;

/// Values below this fraction of the unscattered peak are left inactive (keeps the file sparse).
constexpr double FLOOR_FRACTION = 1e-6;

template <class Field>
openvdb::FloatGrid::Ptr revolve(const BeamKernel& k, const std::string& name, Field field) {
    const double floor = FLOOR_FRACTION * k.beerLambert(0, 0);
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName(name);
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    // Voxel (i, j, l) is centred at (i h, j h, (l + 0.5) h): x, y about the beam axis, z down.
    auto transform = openvdb::math::Transform::createLinearTransform(k.rBin);
    transform->postTranslate(openvdb::Vec3d(0.0, 0.0, 0.5 * k.rBin));
    grid->setTransform(transform);
    grid->insertMeta("units", openvdb::StringMetadata("positions mm, values mW/mm^2"));
    const int n = int(k.rBins);
    const int nz = int(std::ceil(k.zBins * k.zBin / k.rBin));
    auto access = grid->getAccessor();
    for (int l = 0; l < nz; ++l)
        for (int j = -n; j <= n; ++j)
            for (int i = -n; i <= n; ++i) {
                double r = std::hypot(i * k.rBin, j * k.rBin);
                if (r > n * k.rBin) continue;
                float value = float(field(r, (l + 0.5) * k.rBin));
                if (value > floor) access.setValue(openvdb::Coord(i, j, l), value);
            }
    return grid;
}

}  // namespace

void writeKernelVdb(const std::string& path, const BeamKernel& k) {
    if (k.rBins == 0 || k.zBins == 0 || !(k.rBin > 0) || !(k.zBin > 0))
        throw InputError("beam kernel has no table to save", path);
    double voxels = std::pow(2.0 * k.rBins + 1, 2) * std::ceil(k.zBins * k.zBin / k.rBin);
    if (voxels > MAX_VOXELS)
        throw ResourceError("beam kernel grid of " + std::to_string(uint64_t(voxels)) +
                            " voxels (" + formatBytes(voxels * 4) + ") refused: at most " +
                            std::to_string(uint64_t(MAX_VOXELS)) + "; use fewer or coarser bins");
    vdb::initialise();
    openvdb::GridPtrVec grids{
        revolve(k, "intensity", [&k](double r, double z) { return k.sample(r, z); }),
        revolve(k, "intensity_no_scattering",
                [&k](double r, double z) { return k.beerLambert(r, z); })};
    vdb::writeGrids(path, grids);
}

}  // namespace vpsim::kernel
