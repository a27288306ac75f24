// Saves the Cartesian absorption tally as an OpenVDB grid (OpenVDB headers only here).

#include "core/vdb_file.h"
#include "photon_params.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

namespace vpsim::transport {

void writeAbsorptionVdb(const std::string& path, const McResult& result) {
    const CartesianGrid& g = result.setup.grid;
    const uint64_t voxels = uint64_t(g.nxy) * g.nxy * g.nz;
    if (g.nxy == 0 || result.absorbedGrid.size() != voxels)
        throw InputError("the Monte Carlo run has no Cartesian absorption grid to save", path);
    vdb::initialise();
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("absorbed_fraction");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    // Voxel (ix, iy, iz) spans x in [(ix - nxy/2) v, (ix - nxy/2 + 1) v), z in [iz v, (iz+1) v);
    // OpenVDB puts index points at voxel centres, hence the half-voxel shift.
    auto transform = openvdb::math::Transform::createLinearTransform(g.voxel);
    transform->postTranslate(openvdb::Vec3d(0.5 * g.voxel, 0.5 * g.voxel, 0.5 * g.voxel));
    grid->setTransform(transform);
    grid->insertMeta("units", openvdb::StringMetadata("mm; value = fraction of launched weight"));
    const double scale = 1.0 / double(result.launched());
    auto access = grid->getAccessor();
    const int half = int(g.nxy / 2);
    for (uint32_t iz = 0; iz < g.nz; ++iz)
        for (uint32_t iy = 0; iy < g.nxy; ++iy)
            for (uint32_t ix = 0; ix < g.nxy; ++ix) {
                uint64_t q = result.absorbedGrid[(uint64_t(iz) * g.nxy + iy) * g.nxy + ix];
                if (q)
                    access.setValue(openvdb::Coord(int(ix) - half, int(iy) - half, int(iz)),
                                    float(q * scale));
            }
    vdb::writeGrids(path, {grid});
}

}  // namespace vpsim::transport
