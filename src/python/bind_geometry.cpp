// vpsim.slice: a part (STL file, or vertices and triangles as arrays) sliced into layers, each
// with `vpsim slice --json`'s figures and its contours as (n, 2) arrays; with a pitch also the
// layer's mask (uint8) and coverage (float32) on one raster grid, array[ix, iy].
#include "bind_common.h"
#include "vpsim/core/error.h"
#include "vpsim/core/text.h"
#include "vpsim/geometry/layer_stack.h"
#include "vpsim/geometry/mesh_check.h"
#include "vpsim/geometry/raster.h"
#include "vpsim/geometry/slicer.h"
#include "vpsim/geometry/stl_io.h"

namespace vpsim::python {
namespace {

using namespace geometry;

py::array_t<double> contourArray(const Contour& c) {
    std::vector<double> xy;
    xy.reserve(c.size() * 2);
    for (const auto& p : c) {
        xy.push_back(p.x);
        xy.push_back(p.y);
    }
    return ownedArray(std::move(xy), {py::ssize_t(c.size()), 2});
}

/// A raster of `values` (row-major, row j at y) as array[ix, iy].
template <class T, class U>
py::array_t<T> xyArray(const std::vector<U>& values, const RasterGrid& grid) {
    std::vector<T> out(values.size());
    for (int j = 0; j < grid.height; ++j)
        for (int i = 0; i < grid.width; ++i)
            out[size_t(i) * grid.height + j] = T(values[size_t(j) * grid.width + i]);
    return ownedArray(std::move(out), {grid.width, grid.height});
}

py::dict slice(const py::handle& part, const py::handle& layerThickness, const py::dict& a,
               const py::object& progress) {
    const Mesh mesh = partMesh(part, a["scale"].cast<double>());
    SliceOptions options;
    options.layerThickness = quantity(layerThickness, dim::LENGTH, "layer_thickness");
    if (!(options.layerThickness > 0)) throw InputError("must be > 0", "", "layer_thickness");
    options.planePosition = a["plane"].cast<double>();
    if (!a["z_start"].is_none()) options.zStart = quantity(a["z_start"], dim::LENGTH, "z_start");
    const Bounds bounds = mesh.bounds();
    if (options.layerThickness > bounds.hi.z - bounds.lo.z)
        throw InputError("layer thickness " + formatQuantity(options.layerThickness) +
                             " mm is more than the part's height " +
                             formatQuantity(bounds.hi.z - bounds.lo.z) + " mm",
                         "", "layer_thickness");
    const int count = layerCount(mesh, options);
    if (count > 1000000)
        throw ResourceError("slicing into " + std::to_string(count) +
                            " layers would take minutes (more than a million): use a thicker "
                            "layer_thickness");
    std::vector<int> only;
    if (!a["layers"].is_none()) only = a["layers"].cast<std::vector<int>>();
    const std::string source = py::isinstance<py::tuple>(part) || py::isinstance<py::list>(part)
                                   ? std::string("arrays")
                                   : toJson(part, "part").get<std::string>();
    const LayerStack stack =
        withoutGil(progress, [&] { return sliceToStack(mesh, options, source, only); });

    std::optional<RasterGrid> grid;
    if (!a["pitch"].is_none()) {
        const double pitch = quantity(a["pitch"], dim::LENGTH, "pitch");
        if (!(pitch > 0)) throw InputError("must be positive", "", "pitch");
        grid =
            RasterGrid::covering({bounds.lo.x, bounds.lo.y}, {bounds.hi.x, bounds.hi.y}, pitch, 2);
    }
    py::dict out;
    out["file"] = source;
    out["layer_thickness_mm"] = options.layerThickness;
    out["plane_position"] = options.planePosition;
    out["layer_count"] = count;
    py::list layers;
    for (const Layer& layer : stack.layers) {
        py::dict l;
        l["index"] = layer.index;
        l["z"] = layer.z;
        l["z_bottom"] = layer.zBottom;
        l["area"] = layer.region.area();
        l["perimeter"] = layer.region.perimeter();
        l["outer_contours"] = layer.region.outerCount();
        l["holes"] = layer.region.holeCount();
        py::list parts, contours;
        for (const PolygonWithHoles& p : layer.region.parts()) {
            py::dict d;
            d["outer"] = contourArray(p.outer);
            py::list holes;
            for (const Contour& h : p.holes) holes.append(contourArray(h));
            d["holes"] = holes;
            parts.append(d);
        }
        for (const Contour& c : layer.region.contours()) contours.append(contourArray(c));
        l["parts"] = parts;
        l["contours"] = contours;
        if (grid) {
            l["mask"] = xyArray<uint8_t>(rasterizeBinary(layer.region, *grid), *grid);
            l["coverage"] = xyArray<float>(rasterizeCoverage(layer.region, *grid), *grid);
        }
        layers.append(l);
    }
    out["layers"] = layers;
    if (grid) {
        out["raster_origin"] = py::make_tuple(grid->origin.x, grid->origin.y);
        out["raster_pitch"] = grid->pitch;
    }
    return out;
}

}  // namespace

void bindGeometry(py::module_& m) {
    m.def("_slice", &slice, py::arg("part"), py::arg("layer_thickness"), py::arg("arguments"),
          py::arg("progress"));
}

}  // namespace vpsim::python
