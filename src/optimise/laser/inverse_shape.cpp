#include "vpsim/optimise/laser/inverse_shape.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "vpsim/core/error.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/geometry/raster.h"
#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/optimise/laser/exposure_error.h"

namespace vpsim::optimise {
namespace {

using exposure::ExposureField;
using exposure::SurfaceGrid;

/// Height rank of field slice (k, s): 0 at the bottom of layer 0, increasing upwards.
size_t fieldIndex(size_t rank, int n) {
    const size_t k = rank / n, s = size_t(n - 1) - rank % n;
    return k * n + s;
}

/// Vertical distance (mm) from each voxel centre to the nearest state change above (`up`) and
/// below it in its column (infinite when there is none).
void verticalDistances(const std::vector<std::vector<char>>& inside, int n, double voxelHeight,
                       std::vector<std::vector<float>>& up, std::vector<std::vector<float>>& down) {
    const size_t slices = inside.size(), cells = slices ? inside[0].size() : 0;
    const float inf = std::numeric_limits<float>::infinity();
    up.assign(slices, std::vector<float>(cells, inf));
    down = up;
    for (size_t c = 0; c < cells; ++c) {
        float since = inf;  // distance to the change below, going up
        for (size_t r = 0; r < slices; ++r) {
            const size_t v = fieldIndex(r, n);
            if (r > 0 && inside[v][c] != inside[fieldIndex(r - 1, n)][c])
                since = float(0.5 * voxelHeight);
            else if (r > 0)
                since += float(voxelHeight);
            down[v][c] = since;
        }
        since = inf;
        for (size_t r = slices; r-- > 0;) {
            const size_t v = fieldIndex(r, n);
            if (r + 1 < slices && inside[v][c] != inside[fieldIndex(r + 1, n)][c])
                since = float(0.5 * voxelHeight);
            else if (r + 1 < slices)
                since += float(voxelHeight);
            up[v][c] = since;
        }
    }
}

}  // namespace

ShapeTargets shapeTargets(const exposure::ExposureGrid& grid, double layerThickness,
                          double attenuationLength,
                          const std::vector<geometry::PolygonSet>& sliceRegions,
                          double criticalDose, const ShapeParameters& p) {
    const int n = grid.slicesPerLayer;
    if (sliceRegions.empty() || sliceRegions.size() % size_t(n) != 0)
        throw InputError("shape objective: the slice regions are not whole layers");
    if (!(criticalDose > 0)) throw InputError("shape objective: Ec must be positive");
    const double vh = layerThickness / n;
    ShapeTargets t;
    t.criticalDose = criticalDose;
    t.voxelVolume = grid.pitch * grid.pitch * vh;
    t.uniformity = p.uniformity;
    t.meanInside = criticalDose;
    const geometry::RasterGrid raster = grid.raster();
    const double reach = std::max(p.wallBand, grid.pitch);
    std::vector<std::vector<float>> planar(sliceRegions.size());
    for (size_t v = 0; v < sliceRegions.size(); ++v) {
        const std::vector<uint8_t> in = geometry::rasterizeBinary(sliceRegions[v], raster);
        t.inside.emplace_back(in.begin(), in.end());
        planar[v] = sliceRegions[v].empty()
                        ? std::vector<float>(in.size(), float(reach))
                        : geometry::makeTargetMap(sliceRegions[v], raster, reach).signedDistance;
    }
    std::vector<std::vector<float>> up, down;
    verticalDistances(t.inside, n, vh, up, down);
    const double downReach = 3 * attenuationLength;
    t.bound.resize(sliceRegions.size());
    t.weight.resize(sliceRegions.size());
    for (size_t v = 0; v < sliceRegions.size(); ++v) {
        const size_t cells = t.inside[v].size();
        t.bound[v].resize(cells);
        t.weight[v].resize(cells);
        for (size_t c = 0; c < cells; ++c) {
            const bool in = t.inside[v][c];
            const double d =
                std::min({double(std::abs(planar[v][c])), double(up[v][c]), double(down[v][c])});
            const double m = p.margin * std::min(1.0, d / grid.pitch);
            t.bound[v][c] = float(criticalDose * (in ? 1 + m : 1 - m));
            double w = 1;
            if (d <= p.wallBand) w += p.wallWeight;
            if (!in && up[v][c] <= downReach) w += p.downFacingWeight;
            t.weight[v][c] = float(w);
        }
    }
    return t;
}

void levelTargets(ShapeTargets& t, const ExposureField& start) {
    if (start.size() != t.inside.size())
        throw InputError("shape objective: the start field differs from the targets in slices");
    double total = 0, count = 0;
    for (size_t v = 0; v < start.size(); ++v) {
        double sum = 0, n = 0;
        for (size_t c = 0; c < start[v].values.size(); ++c)
            if (t.inside[v][c]) sum += start[v].values[c], n += 1;
        total += sum;
        count += n;
        const double level = std::max(n > 0 ? sum / n : 0.0, t.criticalDose);
        const float scale = float(std::pow(t.criticalDose / level, 2));
        for (float& w : t.weight[v]) w *= scale;
    }
    t.meanInside = std::max(count > 0 ? total / count : 0.0, t.criticalDose);
    // The spread is relative to Ebar, not Ec: mu ((E - Ebar) / Ebar)^2.
    t.uniformity *= std::pow(t.criticalDose / t.meanInside, 2);
}

double shapeObjective(const ShapeTargets& t, const ExposureField& field, ExposureField* gradient) {
    if (field.size() != t.inside.size())
        throw InputError("shape objective: the field differs from the targets in slices");
    const double ec2 = t.criticalDose * t.criticalDose, scale = t.voxelVolume / ec2;
    if (gradient) {
        gradient->resize(field.size());
        for (size_t v = 0; v < field.size(); ++v) {
            const SurfaceGrid& f = field[v];
            (*gradient)[v] = SurfaceGrid(f.nx, f.ny, f.originX, f.originY, f.pitch);
        }
    }
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, field.size()), 0.0,
        [&](const tbb::blocked_range<size_t>& range, double sum) {
            for (size_t v = range.begin(); v != range.end(); ++v) {
                const std::vector<float>& e = field[v].values;
                float* g = gradient ? (*gradient)[v].values.data() : nullptr;
                for (size_t c = 0; c < e.size(); ++c) {
                    const double b = t.bound[v][c], w = t.weight[v][c];
                    double dj = 0;
                    if (t.inside[v][c]) {
                        const double h = std::max(0.0, b - e[c]);
                        const double u = e[c] - t.meanInside;
                        sum += 0.5 * scale * (w * h * h + t.uniformity * u * u);
                        dj = scale * (-w * h + t.uniformity * u);
                    } else {
                        const double h = std::max(0.0, e[c] - b);
                        sum += 0.5 * scale * w * h * h;
                        dj = scale * w * h;
                    }
                    if (g) g[c] = float(dj);
                }
            }
            return sum;
        },
        [](double a, double b) { return a + b; });
}

ShapeProblem::ShapeProblem(exposure::ExposureModel& model, const ShapeTargets& targets,
                           std::vector<std::vector<size_t>> dots)
    : mModel(model), mTargets(targets), mDots(std::move(dots)) {
    mCellArea = model.grid().pitch * model.grid().pitch;
    for (const auto& layer : mDots) {
        mOffset.push_back(mSize);
        mSize += layer.size();
    }
}

std::vector<SurfaceGrid> ShapeProblem::dotDeposits(const std::vector<double>& x) const {
    std::vector<SurfaceGrid> out(mDots.size(), mModel.grid().surface());
    for (size_t k = 0; k < mDots.size(); ++k)
        for (size_t d = 0; d < mDots[k].size(); ++d)
            out[k].values[mDots[k][d]] = float(x[mOffset[k] + d] / mCellArea);
    return out;
}

std::vector<SurfaceGrid> ShapeProblem::deposits(const std::vector<double>& x) const {
    std::vector<SurfaceGrid> out = dotDeposits(x);
    for (size_t k = 0; k < mFixed.size() && k < out.size(); ++k)
        for (size_t c = 0; c < out[k].values.size(); ++c) out[k].values[c] += mFixed[k].values[c];
    return out;
}

double ShapeProblem::valueOfDeposits(const std::vector<SurfaceGrid>& deposits) const {
    return shapeObjective(mTargets, mModel.stack(deposits));
}

double ShapeProblem::value(const std::vector<double>& x) const {
    return valueOfDeposits(deposits(x));
}

ExposureField ShapeProblem::field(const std::vector<double>& x) const {
    return mModel.stack(deposits(x));
}

double ShapeProblem::valueAt(const ExposureField& field, std::vector<double>* gradient) const {
    if (!gradient) return shapeObjective(mTargets, field);
    ExposureField dj;
    const double j = shapeObjective(mTargets, field, &dj);
    const std::vector<SurfaceGrid> back = mModel.stackAdjoint(dj);
    gradient->assign(mSize, 0.0);
    for (size_t k = 0; k < mDots.size(); ++k)
        for (size_t d = 0; d < mDots[k].size(); ++d)
            (*gradient)[mOffset[k] + d] = back[k].values[mDots[k][d]] / mCellArea;
    return j;
}

double ShapeProblem::valueAndGradient(const std::vector<double>& x,
                                      std::vector<double>& gradient) const {
    return valueAt(field(x), &gradient);
}

std::vector<double> ShapeProblem::rowSums() const {
    ExposureField field = mModel.stack(dotDeposits(std::vector<double>(mSize, 1.0)));
    const double scale = mTargets.voxelVolume / (mTargets.criticalDose * mTargets.criticalDose);
    for (size_t v = 0; v < field.size(); ++v)
        for (size_t c = 0; c < field[v].values.size(); ++c)
            field[v].values[c] *=
                float(scale *
                      (mTargets.weight[v][c] + (mTargets.inside[v][c] ? mTargets.uniformity : 0)));
    const std::vector<SurfaceGrid> back = mModel.stackAdjoint(field);
    std::vector<double> sums(mSize);
    for (size_t k = 0; k < mDots.size(); ++k)
        for (size_t d = 0; d < mDots[k].size(); ++d)
            sums[mOffset[k] + d] =
                1.001 * std::max(double(back[k].values[mDots[k][d]]) / mCellArea, 1e-300);
    return sums;
}

}  // namespace vpsim::optimise
