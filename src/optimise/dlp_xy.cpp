#include "vpsim/optimise/dlp_xy.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"
#include "vpsim/exposure/exposure_engine.h"

namespace vpsim::optimise {

using Field = std::vector<std::vector<float>>;

struct DlpBlurOperator::State {
    int width, height, layers, sub, margin;
    double rateConstant;
    exposure::ExposureGrid grid;
    std::unique_ptr<exposure::ExposureEngine> engine;
    std::vector<long> pixelOfCell;
};

DlpBlurOperator::DlpBlurOperator(int width, int height, int layers, const DlpColumnProblem& p,
                                 const DlpXyOptions& o)
    : mState(std::make_unique<State>()) {
    if (width <= 0 || height <= 0 || layers <= 0 || o.subsamples < 1 || !(o.blurRadius > 0.0) ||
        !(o.pixelPitch > 0.0))
        throw InputError("xy coupling: sizes, subsamples, pixel pitch and blur must be positive");
    State& s = *mState;
    s.width = width, s.height = height, s.layers = layers, s.sub = o.subsamples;
    s.rateConstant = p.rateConstant;
    const double pitch = o.pixelPitch / o.subsamples;
    s.margin = exposure::blurHalfWidth(o.blurRadius, pitch) + 1;  // void the blur reaches
    s.grid.nx = width * s.sub + 2 * s.margin;
    s.grid.ny = height * s.sub + 2 * s.margin;
    s.grid.originX = -s.margin * pitch;
    s.grid.originY = -s.margin * pitch;
    s.grid.pitch = pitch;
    s.grid.slicesPerLayer = 1;
    kernel::FittedBeam beam{o.blurRadius, 1.0 / p.attenuation, 0.0, 1.0};
    s.engine = std::make_unique<exposure::ExposureEngine>(s.grid, beam, p.layerThickness);
    s.pixelOfCell.assign(size_t(s.grid.nx) * size_t(s.grid.ny), -1);
    for (int j = 0; j < s.grid.ny; ++j)
        for (int i = 0; i < s.grid.nx; ++i) {
            int x = (i - s.margin), y = (j - s.margin);
            if (x < 0 || y < 0 || x >= width * s.sub || y >= height * s.sub) continue;
            s.pixelOfCell[size_t(j) * s.grid.nx + i] = long(y / s.sub) * width + x / s.sub;
        }
}

DlpBlurOperator::~DlpBlurOperator() = default;
int DlpBlurOperator::cellsX() const {
    return mState->grid.nx;
}
int DlpBlurOperator::cellsY() const {
    return mState->grid.ny;
}
long DlpBlurOperator::pixelOf(int i, int j) const {
    return mState->pixelOfCell[size_t(j) * mState->grid.nx + i];
}

Field DlpBlurOperator::apply(const Field& dose) {
    State& s = *mState;
    std::vector<exposure::SurfaceGrid> deposits(size_t(s.layers), s.grid.surface());
    for (int k = 0; k < s.layers; ++k)
        for (size_t c = 0; c < s.pixelOfCell.size(); ++c)
            if (s.pixelOfCell[c] >= 0) deposits[k].values[c] = dose[k][size_t(s.pixelOfCell[c])];
    exposure::ExposureField field = s.engine->stack(deposits);
    Field out(size_t(s.layers));
    for (int k = 0; k < s.layers; ++k) {
        out[k] = std::move(field[size_t(k)].values);
        for (float& v : out[k]) v *= float(-s.rateConstant);
    }
    return out;
}

Field DlpBlurOperator::applyAdjoint(const Field& cells) {
    State& s = *mState;
    exposure::ExposureField field(size_t(s.layers), s.grid.surface());
    for (int k = 0; k < s.layers; ++k) field[size_t(k)].values = cells[size_t(k)];
    std::vector<exposure::SurfaceGrid> adjoint = s.engine->stackAdjoint(field);
    Field out(size_t(s.layers), std::vector<float>(size_t(s.width) * s.height, 0.0f));
    for (int k = 0; k < s.layers; ++k)
        for (size_t c = 0; c < s.pixelOfCell.size(); ++c)
            if (s.pixelOfCell[c] >= 0)
                out[k][size_t(s.pixelOfCell[c])] +=
                    float(-s.rateConstant) * adjoint[size_t(k)].values[c];
    return out;
}

namespace {

double squaredResidual(const Field& phi, const Field& target, Field* residual) {
    double sum = 0.0;
    for (size_t k = 0; k < phi.size(); ++k)
        for (size_t c = 0; c < phi[k].size(); ++c) {
            double r = double(phi[k][c]) - target[k][c];
            sum += r * r;
            if (residual) (*residual)[k][c] = float(r);
        }
    return sum;
}

/// Mean XY displacement (mm) of the cured contour: misclassified cell area / designed perimeter.
double contourError(const Field& phi, const Field& target, double ecPhi, int nx, int ny,
                    double pitch) {
    double wrong = 0.0, perimeter = 0.0;
    for (size_t k = 0; k < phi.size(); ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                size_t c = size_t(j) * nx + i;
                bool solid = target[k][c] <= 0.0f;  // phi_obj < 0 inside, penalty >= 0 outside
                bool cured = phi[k][c] <= ecPhi;
                wrong += solid != cured;
                if (i + 1 < nx) perimeter += solid != (target[k][c + 1] <= 0.0f);
                if (j + 1 < ny) perimeter += solid != (target[k][c + size_t(nx)] <= 0.0f);
            }
    return perimeter > 0 ? wrong * pitch / perimeter : 0.0;
}

}  // namespace

DlpXyResult optimiseDlpPartXy(const DlpLayerStack& part, const DlpPartOptions& options,
                              const DlpXyOptions& xy, const DlpPartResult* columns) {
    DlpPartResult own;
    if (!columns) own = optimiseDlpPart(part, options), columns = &own;
    const auto start = std::chrono::steady_clock::now();
    const int layers = int(part.layers.size());
    const size_t pixels = size_t(part.width) * part.height;
    DlpBlurOperator op(part.width, part.height, layers, options.problem, xy);
    // Boxes: each pixel keeps its column pattern and Eq. 10 bounds.
    Field lo(size_t(layers), std::vector<float>(pixels, 0.0f)), hi = lo;
    for (size_t p = 0; p < pixels; ++p) {
        std::vector<uint8_t> solid(size_t(layers), 0), exposed(size_t(layers), 0);
        bool any = false;
        for (int k = 0; k < layers; ++k) {
            solid[k] = part.layers[k][p] ? 1 : 0;
            exposed[k] = columns->dose[k][p] > 0.0f;
            any = any || solid[k];
        }
        if (!any) continue;
        std::vector<double> l, h;
        exposureBounds(exposed, solid, options.problem, l, h);
        for (int k = 0; k < layers; ++k) lo[k][p] = float(l[k]), hi[k][p] = float(h[k]);
    }
    const double inside = std::log1p(-options.problem.targetConversion);
    Field target(size_t(layers), std::vector<float>(size_t(op.cellsX()) * op.cellsY()));
    for (int k = 0; k < layers; ++k)
        for (int j = 0; j < op.cellsY(); ++j)
            for (int i = 0; i < op.cellsX(); ++i) {
                long p = op.pixelOf(i, j);
                bool solid = p >= 0 && part.layers[k][size_t(p)];
                target[k][size_t(j) * op.cellsX() + i] =
                    float(solid ? inside : options.problem.penalty);
            }
    const double scale = 1.0 / double(xy.subsamples * xy.subsamples);
    // Lipschitz constant of grad F = 2 scale A^T A by power iteration (8 steps, 10 % margin).
    Field v = hi;
    double lambda = 1.0;
    for (int it = 0; it < 8; ++it) {
        Field w = op.applyAdjoint(op.apply(v));
        double norm = 0.0, vnorm = 0.0;
        for (size_t k = 0; k < w.size(); ++k)
            for (size_t p = 0; p < pixels; ++p)
                norm += double(w[k][p]) * w[k][p], vnorm += double(v[k][p]) * v[k][p];
        lambda = std::sqrt(norm / std::max(vnorm, 1e-300));
        for (size_t k = 0; k < w.size(); ++k)
            for (size_t p = 0; p < pixels; ++p) v[k][p] = float(w[k][p] / lambda);
    }
    const double lipschitz = 2.0 * scale * lambda * 1.1;
    Field x = columns->dose, y = x, residual = target;
    const Field phi0 = op.apply(x);
    DlpXyResult out;
    out.objectiveColumns = scale * squaredResidual(phi0, target, nullptr);
    double t = 1.0;
    for (int it = 0; it < xy.iterations; ++it) {
        squaredResidual(op.apply(y), target, &residual);
        Field g = op.applyAdjoint(residual);
        Field next = y;
        for (size_t k = 0; k < next.size(); ++k)
            for (size_t p = 0; p < pixels; ++p)
                next[k][p] = std::clamp(float(y[k][p] - 2.0 * scale * g[k][p] / lipschitz),
                                        lo[k][p], hi[k][p]);
        const double tNext = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * t * t));
        const float momentum = float((t - 1.0) / tNext);
        for (size_t k = 0; k < next.size(); ++k)
            for (size_t p = 0; p < pixels; ++p)
                y[k][p] =
                    std::clamp(next[k][p] + momentum * (next[k][p] - x[k][p]), lo[k][p], hi[k][p]);
        x = std::move(next);
        t = tNext;
    }
    const Field phi = op.apply(x);
    out.objectiveXy = scale * squaredResidual(phi, target, nullptr);
    if (out.objectiveXy > out.objectiveColumns)
        x = columns->dose, out.objectiveXy = out.objectiveColumns;
    const double ecPhi = std::log1p(-options.problem.gelPoint);  // phi at the gel point
    const double pitch = xy.pixelPitch / xy.subsamples;
    out.contourErrorColumns = contourError(phi0, target, ecPhi, op.cellsX(), op.cellsY(), pitch);
    out.contourErrorXy = contourError(out.objectiveXy < out.objectiveColumns ? phi : phi0, target,
                                      ecPhi, op.cellsX(), op.cellsY(), pitch);
    out.doses = *columns;
    out.doses.dose = std::move(x);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.peakFieldMiB = 6.0 * double(layers) * op.cellsX() * op.cellsY() * 4.0 / (1 << 20);
    return out;
}

}  // namespace vpsim::optimise
