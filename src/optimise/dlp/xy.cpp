#include "vpsim/optimise/dlp/xy.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"

namespace vpsim::optimise {

using Field = std::vector<std::vector<float>>;

struct DlpShapeObjective::State {
    DlpBlurOperator op;
    int nx = 0, ny = 0;
    double ec = 0.0, rateConstant = 0.0, margin = 0.0, beta = 0.0, target = 0.0;
    double pitch = 0.0;
    double insideCells = 0.0;
    std::vector<std::vector<uint8_t>> inside;  ///< per layer, per cell: inside the part
    std::vector<std::vector<float>> weight;    ///< per layer, per cell: w_c
    std::vector<double> perimeter;             ///< per layer, mm: solid/void cell edges x pitch
    double maxWeight = 1.0;

    State(const DlpLayerStack& part, const DlpColumnProblem& p, const DlpXyOptions& o)
        : op(part.width, part.height, int(part.layers.size()), p, o) {}
};

namespace {

/// Cells within `reach` cells (Chebyshev) of a cell set in `mark`: separable max filter.
std::vector<uint8_t> dilate(const std::vector<uint8_t>& mark, int nx, int ny, int reach) {
    std::vector<uint8_t> rows(mark.size(), 0), out(mark.size(), 0);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            if (mark[size_t(j) * nx + i])
                for (int o = std::max(0, i - reach); o <= std::min(nx - 1, i + reach); ++o)
                    rows[size_t(j) * nx + o] = 1;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            if (rows[size_t(j) * nx + i])
                for (int o = std::max(0, j - reach); o <= std::min(ny - 1, j + reach); ++o)
                    out[size_t(o) * nx + i] = 1;
    return out;
}

}  // namespace

DlpShapeObjective::DlpShapeObjective(const DlpLayerStack& part, const DlpColumnProblem& p,
                                     const DlpXyOptions& o, double uniformityTarget)
    : mState(std::make_unique<State>(part, p, o)) {
    if (!(o.margin >= 0.0 && o.margin < 1.0) || !(o.contourWeight >= 0.0) || o.contourCells < 0 ||
        !(o.uniformityWeight >= 0.0) || !(uniformityTarget > 0.0))
        throw InputError(
            "xy coupling: margin in [0, 1), contour weight, contour cells and "
            "uniformity weight >= 0, uniformity target > 0");
    State& s = *mState;
    s.nx = s.op.cellsX(), s.ny = s.op.cellsY();
    s.ec = cure::fppGelDose(p.rateConstant, p.gelPoint);
    s.rateConstant = p.rateConstant;
    s.margin = o.margin, s.beta = o.uniformityWeight, s.target = uniformityTarget;
    s.pitch = o.pixelPitch / o.subsamples;
    s.maxWeight = 1.0 + o.contourWeight;
    const size_t cells = size_t(s.nx) * s.ny, layers = part.layers.size();
    s.inside.assign(layers, std::vector<uint8_t>(cells, 0));
    for (size_t k = 0; k < layers; ++k)
        for (int j = 0; j < s.ny; ++j)
            for (int i = 0; i < s.nx; ++i) {
                const long px = s.op.pixelOf(i, j);
                s.inside[k][size_t(j) * s.nx + i] = px >= 0 && part.layers[k][size_t(px)] != 0;
            }
    s.weight.assign(layers, std::vector<float>(cells, 1.0f));
    s.perimeter.assign(layers, 0.0);
    for (size_t k = 0; k < layers; ++k) {
        const std::vector<uint8_t>& in = s.inside[k];
        std::vector<uint8_t> change(cells, 0);
        for (int j = 0; j < s.ny; ++j)
            for (int i = 0; i < s.nx; ++i) {
                const size_t c = size_t(j) * s.nx + i;
                const bool right = i + 1 < s.nx && in[c] != in[c + 1];
                const bool up = j + 1 < s.ny && in[c] != in[c + size_t(s.nx)];
                s.perimeter[k] += (double(right) + double(up)) * s.pitch;
                change[c] |= right || up;
                if (right) change[c + 1] = 1;
                if (up) change[c + size_t(s.nx)] = 1;
                // A solid/void change against the layer above or below (down- and up-facing).
                if ((k + 1 < layers && s.inside[k + 1][c] != in[c]) ||
                    (k > 0 && s.inside[k - 1][c] != in[c]))
                    change[c] = 1;
            }
        const std::vector<uint8_t> near = dilate(change, s.nx, s.ny, o.contourCells);
        for (size_t c = 0; c < cells; ++c) {
            if (near[c]) s.weight[k][c] = float(s.maxWeight);
            s.insideCells += in[c];
        }
    }
    if (s.insideCells <= 0.0) throw InputError("xy coupling: the part has no solid cell");
}

DlpShapeObjective::~DlpShapeObjective() = default;

DlpBlurOperator& DlpShapeObjective::blur() {
    return mState->op;
}

double DlpShapeObjective::value(const Field& dose, Field* gradient) {
    State& s = *mState;
    Field phi = s.op.apply(dose);  // -K E
    const size_t layers = phi.size();
    std::vector<double> perLayer(layers, 0.0);
    tbb::parallel_for(size_t(0), layers, [&](size_t k) {
        double sum = 0.0;
        for (size_t c = 0; c < phi[k].size(); ++c) {
            const double e = double(phi[k][c]) / -s.rateConstant / s.ec;  // E / Ec
            const double w = s.weight[k][c];
            double dJdE = 0.0;  // per Ec
            if (s.inside[k][c]) {
                const double h = std::max(0.0, 1.0 + s.margin - e);
                const double u = (e * s.ec - s.target) / s.target;
                sum += w * h * h + s.beta * u * u;
                dJdE = -2.0 * w * h + 2.0 * s.beta * u * s.ec / s.target;
            } else {
                const double h = std::max(0.0, e - (1.0 - s.margin));
                sum += w * h * h;
                dJdE = 2.0 * w * h;
            }
            // d(E/Ec)/d(phi) = -1 / (K Ec); the operator's adjoint carries the -K of A.
            phi[k][c] = float(dJdE / (-s.rateConstant * s.ec) / s.insideCells);
        }
        perLayer[k] = sum;
    });
    double total = 0.0;
    for (double v : perLayer) total += v;
    if (gradient) *gradient = s.op.applyAdjoint(phi);
    return total / s.insideCells;
}

double DlpShapeObjective::contourError(const Field& dose) {
    State& s = *mState;
    const Field phi = s.op.apply(dose);
    const float curedPhi = float(-s.rateConstant * s.ec);  // phi <= this: E >= Ec
    double sum = 0.0;
    int counted = 0;
    for (size_t k = 0; k < phi.size(); ++k) {
        if (!(s.perimeter[k] > 0.0)) continue;
        size_t wrong = 0;
        for (size_t c = 0; c < phi[k].size(); ++c)
            wrong += (phi[k][c] <= curedPhi) != (s.inside[k][c] != 0);
        sum += double(wrong) * s.pitch * s.pitch / s.perimeter[k];
        ++counted;
    }
    return counted ? sum / counted : 0.0;
}

double DlpShapeObjective::lipschitz(const Field& start) {
    State& s = *mState;
    // ||A^T A|| by power iteration (8 steps) from the start's doses, 10 % margin; J's Hessian is
    // at most (2 w_max + 2 beta Ec^2/E_t^2) / (K Ec)^2 / N_inside times A^T A.
    Field v = start;
    double lambda = 1.0;
    for (int it = 0; it < 8; ++it) {
        Field w = s.op.applyAdjoint(s.op.apply(v));
        double norm = 0.0, vnorm = 0.0;
        for (size_t k = 0; k < w.size(); ++k)
            for (size_t p = 0; p < w[k].size(); ++p)
                norm += double(w[k][p]) * w[k][p], vnorm += double(v[k][p]) * v[k][p];
        if (!(vnorm > 0.0) || !(norm > 0.0)) break;
        lambda = std::sqrt(norm / vnorm);
        for (size_t k = 0; k < w.size(); ++k)
            for (size_t p = 0; p < w[k].size(); ++p) v[k][p] = float(w[k][p] / lambda);
    }
    const double ke = s.rateConstant * s.ec;
    const double curvature = 2.0 * s.maxWeight + 2.0 * s.beta * s.ec * s.ec / (s.target * s.target);
    return 1.1 * lambda * curvature / (ke * ke) / s.insideCells;
}

}  // namespace vpsim::optimise
