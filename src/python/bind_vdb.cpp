// vpsim.read_vdb: a float grid of a .vdb file as a dense float32 array in C order with axes
// (x, y, z), array[i, j, k] the voxel at index (i0 + i, j0 + j, k0 + k) (OpenVDB's ZYX dense
// layout is exactly that order), with the index offset, voxel size and world origin.
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>

#include "bind_common.h"
#include "core/vdb_file.h"
#include "vpsim/core/error.h"
#include "vpsim/core/resources.h"

namespace vpsim::python {
namespace {

py::dict readVdb(const std::string& path, const std::string& name, const py::object& shape) {
    vdb::initialise();
    openvdb::GridBase::Ptr base;
    try {
        openvdb::io::File file(path);
        file.open();
        if (name.empty()) {
            openvdb::GridPtrVecPtr grids = file.getGrids();
            for (const auto& g : *grids)
                if (g->isType<openvdb::FloatGrid>()) {
                    base = g;
                    break;
                }
        } else if (file.hasGrid(name)) {
            base = file.readGrid(name);
        }
        file.close();
    } catch (const openvdb::Exception& e) {
        throw InputError(std::string("cannot read OpenVDB file: ") + e.what(), path);
    }
    if (!base || !base->isType<openvdb::FloatGrid>())
        throw InputError(name.empty() ? "no float grid in the file" : "no float grid " + name,
                         path);
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    openvdb::CoordBBox box;
    if (shape.is_none()) {
        box = grid->evalActiveVoxelBoundingBox();
        if (box.empty()) box = openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(0));
    } else {
        const auto n = shape.cast<std::vector<int>>();
        if (n.size() != 3 || n[0] < 1 || n[1] < 1 || n[2] < 1)
            throw InputError("expected three positive sizes", "", "shape");
        box = openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(n[0] - 1, n[1] - 1, n[2] - 1));
    }
    const openvdb::Coord dim = box.dim();
    checkMemory(RunContext{}, double(dim.x()) * dim.y() * dim.z() * 4.0,
                "the dense copy of " + path, "give a smaller shape");
    py::array_t<float> array({py::ssize_t(dim.x()), py::ssize_t(dim.y()), py::ssize_t(dim.z())});
    float* data = array.mutable_data();
    {
        py::gil_scoped_release release;
        openvdb::tools::Dense<float, openvdb::tools::LayoutZYX> dense(box, data);
        dense.fill(0.0f);
        openvdb::tools::copyToDense(*grid, dense);
    }
    const openvdb::Vec3d voxel = grid->voxelSize();
    const openvdb::Vec3d centre = grid->indexToWorld(box.min());
    py::dict out;
    out["array"] = array;
    out["index_min"] = py::make_tuple(box.min().x(), box.min().y(), box.min().z());
    out["voxel_size"] = py::make_tuple(voxel.x(), voxel.y(), voxel.z());
    // the corner of voxel index_min (vpsim's grids put voxel centres at corner + voxel / 2)
    out["origin"] = py::make_tuple(centre.x() - 0.5 * voxel.x(), centre.y() - 0.5 * voxel.y(),
                                   centre.z() - 0.5 * voxel.z());
    out["name"] = grid->getName();
    out["active_voxels"] = grid->activeVoxelCount();
    return out;
}

}  // namespace

void bindComponentsVdb(py::module_& m) {
    m.def("_read_vdb", &readVdb, py::arg("path"), py::arg("name"), py::arg("shape"));
}

}  // namespace vpsim::python
