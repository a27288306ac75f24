#include "vpsim/optimise/dlp/xy.h"

#include "vpsim/core/error.h"
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

}  // namespace vpsim::optimise
