#include "vpsim/exposure/exposure_model.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"
#include "vpsim/exposure/deposit.h"

namespace vpsim::exposure {

ExposureGrid ExposureGrid::covering(double xmin, double ymin, double xmax, double ymax,
                                    double margin, double pitch, int slicesPerLayer) {
    if (!(pitch > 0)) throw InputError("exposure grid pitch must be positive");
    ExposureGrid grid;
    grid.pitch = pitch;
    grid.slicesPerLayer = slicesPerLayer;
    grid.originX = xmin - margin;
    grid.originY = ymin - margin;
    grid.nx = int(std::ceil((xmax - xmin + 2 * margin) / pitch));
    grid.ny = int(std::ceil((ymax - ymin + 2 * margin) / pitch));
    return grid;
}

ExposureGrid ExposureGrid::window(const CellWindow& w) const {
    ExposureGrid out = *this;
    out.firstI = w.i0;
    out.firstJ = w.j0;
    out.nx = w.width();
    out.ny = w.height();
    return out;
}

double ExposureModel::forward(int layers, const std::function<void(int, SurfaceGrid&)>& fill,
                              const std::function<double(int)>& top, const SliceSink& sink) {
    SurfaceGrid deposit = grid().surface();
    beginLayers(layers);
    double seconds = 0;
    Progress progress(name() + " exposure", layers);
    for (int k = layers - 1; k >= 0; --k) {
        std::fill(deposit.values.begin(), deposit.values.end(), 0.0f);
        fill(k, deposit);
        seconds += addLayer(k, deposit);
        emitLayer(k, top(k), sink);
        progress.advance();
    }
    return seconds;
}

double ExposureModel::run(const plan::ScanPlan& plan, const SliceSink& sink) {
    return forward(
        int(plan.layers.size()),
        [&](int k, SurfaceGrid& deposit) { depositLayer(plan.layers[k], deposit); },
        [&](int k) { return plan.layers[k].z; }, sink);
}

double ExposureModel::run(const plan::ScanPlan& plan, const CellWindow& core,
                          const SliceSink& sink) {
    return run(plan, [&](const ExposureSlice& slice) {
        ExposureSlice owned = slice;
        owned.core = core;
        sink(owned);
    });
}

ExposureField ExposureModel::stack(const std::vector<SurfaceGrid>& deposits) {
    const ExposureGrid& g = grid();
    for (const SurfaceGrid& d : deposits)
        if (d.nx != g.nx || d.ny != g.ny)
            throw InputError("a deposit grid differs from the exposure grid in size");
    const int n = g.slicesPerLayer;
    ExposureField field(deposits.size() * n);
    forward(
        int(deposits.size()), [&](int k, SurfaceGrid& deposit) { deposit = deposits[k]; },
        [&](int k) { return (k + 1) * layerThickness(); },
        [&](const ExposureSlice& s) { field[size_t(s.layer) * n + s.slice] = *s.values; });
    return field;
}

int fieldLayers(const ExposureField& field, const ExposureGrid& grid) {
    const size_t n = size_t(grid.slicesPerLayer);
    if (field.size() % n != 0)
        throw InputError("an exposure field of " + std::to_string(field.size()) +
                         " slices is not a whole number of layers of " + std::to_string(n));
    for (const SurfaceGrid& s : field)
        if (s.nx != grid.nx || s.ny != grid.ny)
            throw InputError("an exposure field slice differs from the exposure grid in size");
    return int(field.size() / n);
}

double dot(const SurfaceGrid& a, const SurfaceGrid& b) {
    if (a.values.size() != b.values.size()) throw InputError("dot: grids differ in size");
    double sum = 0;
    for (size_t c = 0; c < a.values.size(); ++c) sum += double(a.values[c]) * b.values[c];
    return sum;
}

double dot(const ExposureField& a, const ExposureField& b) {
    if (a.size() != b.size()) throw InputError("dot: fields differ in slice count");
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += dot(a[i], b[i]);
    return sum;
}

}  // namespace vpsim::exposure
