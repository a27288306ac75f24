// The joint xy optimisation (xy.h): warm start from the column optima, then FISTA on J.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"
#include "vpsim/cure/cure_model.h"
#include "vpsim/optimise/dlp/xy.h"

namespace vpsim::optimise {

using Field = std::vector<std::vector<float>>;

namespace {

/// Mid-depth doses of one pixel column without blur: E_k = D_k exp(-mu Le / 2), D by Eq. 4.
std::vector<double> midDepthDoses(const Field& dose, size_t pixel, const DlpColumnProblem& p) {
    const size_t n = dose.size();
    const double r = std::exp(-p.attenuation * p.layerThickness);
    const double half = std::exp(-0.5 * p.attenuation * p.layerThickness);
    std::vector<double> e(n);
    double carried = 0.0;
    for (size_t k = n; k-- > 0;) {
        carried = double(dose[k][pixel]) + r * carried;
        e[k] = carried * half;
    }
    return e;
}

/// J of one pixel column without blur (the per-pixel pattern choice of the warm start).
double columnScore(const Field& dose, size_t pixel, const DlpLayerStack& part,
                   const DlpColumnProblem& p, const DlpXyOptions& o, double target) {
    const double ec = cure::fppGelDose(p.rateConstant, p.gelPoint);
    const std::vector<double> e = midDepthDoses(dose, pixel, p);
    double sum = 0.0;
    for (size_t k = 0; k < e.size(); ++k) {
        const bool in = part.layers[k][pixel] != 0;
        const bool change = (k + 1 < e.size() && (part.layers[k + 1][pixel] != 0) != in) ||
                            (k > 0 && (part.layers[k - 1][pixel] != 0) != in);
        const double w = change ? 1.0 + o.contourWeight : 1.0;
        if (in) {
            const double h = std::max(0.0, 1.0 + o.margin - e[k] / ec),
                         u = (e[k] - target) / target;
            sum += w * h * h + o.uniformityWeight * u * u;
        } else {
            const double h = std::max(0.0, e[k] / ec - (1.0 - o.margin));
            sum += w * h * h;
        }
    }
    return sum;
}

/// Eq. 10 boxes of every pixel's pattern (the layers with a non-null dose in `dose`).
void patternBoxes(const DlpLayerStack& part, const DlpColumnProblem& p, const Field& dose,
                  Field& lo, Field& hi) {
    const size_t layers = part.layers.size(), pixels = size_t(part.width) * part.height;
    lo.assign(layers, std::vector<float>(pixels, 0.0f));
    hi = lo;
    for (size_t px = 0; px < pixels; ++px) {
        std::vector<uint8_t> solid(layers, 0), exposed(layers, 0);
        bool any = false;
        for (size_t k = 0; k < layers; ++k) {
            solid[k] = part.layers[k][px] ? 1 : 0;
            exposed[k] = solid[k] && dose[k][px] > 0.0f;
            any = any || solid[k];
        }
        if (!any) continue;
        std::vector<double> l, h;
        if (!exposureBounds(exposed, solid, p, l, h)) {  // keep an unprintable column as it is
            for (size_t k = 0; k < layers; ++k) lo[k][px] = hi[k][px] = dose[k][px];
            continue;
        }
        for (size_t k = 0; k < layers; ++k) lo[k][px] = float(l[k]), hi[k][px] = float(h[k]);
    }
}

}  // namespace

double meanInsideDose(const DlpLayerStack& part, const DlpColumnProblem& p,
                      const DlpPartResult& doses) {
    double sum = 0.0, count = 0.0;
    const size_t pixels = size_t(part.width) * part.height;
    for (size_t px = 0; px < pixels; ++px) {
        const std::vector<double> e = midDepthDoses(doses.dose, px, p);
        for (size_t k = 0; k < e.size(); ++k)
            if (part.layers[k][px]) sum += e[k], count += 1.0;
    }
    return count > 0.0 ? sum / count : 0.0;
}

DlpXyResult optimiseDlpPartXy(const DlpLayerStack& part, const DlpPartOptions& options,
                              const DlpXyOptions& xy, const DlpPartResult* columns) {
    DlpPartResult own;
    if (!columns) own = optimiseDlpPart(part, options), columns = &own;
    const auto start = std::chrono::steady_clock::now();
    const DlpColumnProblem& p = options.problem;
    const bool l2 = options.objective == DlpObjective::ConversionL2;
    DlpXyResult out;
    out.uniformityTarget =
        l2 ? -std::log1p(-p.targetConversion) / p.rateConstant : meanInsideDose(part, p, *columns);
    if (!(out.uniformityTarget > 0.0))
        out.uniformityTarget = cure::fppGelDose(p.rateConstant, p.gelPoint);
    DlpShapeObjective objective(part, p, xy, out.uniformityTarget);
    // One line for the whole stage: its blur passes (warm starts, step size) draw none of their
    // own under it.
    Progress progress("DLP masks: xy coupling (warm starts, step size, FISTA iterations)",
                      uint64_t(xy.iterations));
    // Warm starts: the column optimum; with conversion-l2 also the geometric optimum and the
    // per-pixel mix of the two (each pixel keeps the pattern its own column scores better with).
    Field x = columns->dose;
    out.objectiveColumns = objective.value(x);
    out.objectiveStart = out.objectiveColumns;
    out.start = "columns";
    if (l2 && xy.tryGeometricPattern) {
        DlpPartOptions g = options;
        g.objective = DlpObjective::Geometric;
        g.geometric.margin = xy.margin;
        const DlpPartResult geometric = optimiseDlpPart(part, g);
        Field mixed = x;
        const size_t pixels = size_t(part.width) * part.height;
        for (size_t px = 0; px < pixels; ++px)
            if (columnScore(geometric.dose, px, part, p, xy, out.uniformityTarget) <
                columnScore(x, px, part, p, xy, out.uniformityTarget))
                for (size_t k = 0; k < mixed.size(); ++k) mixed[k][px] = geometric.dose[k][px];
        for (auto [name, candidate] :
             {std::pair<const char*, const Field*>{"geometric", &geometric.dose},
              {"mixed", &mixed}}) {
            const double value = objective.value(*candidate);
            if (value < out.objectiveStart)
                out.objectiveStart = value, x = *candidate, out.start = name;
        }
    }
    Field lo, hi;
    patternBoxes(part, p, x, lo, hi);
    const double step = 1.0 / objective.lipschitz(hi);
    // FISTA from x, restarting the momentum when J rises; the best point evaluated is kept
    // (every evaluated point lies in the boxes), so the result never exceeds the start's J.
    Field best = x, y = x, gradient;
    double bestValue = out.objectiveStart, previous = out.objectiveStart, t = 1.0;
    for (int it = 0; it < xy.iterations; ++it) {
        const double value = objective.value(y, &gradient);
        if (value < bestValue) bestValue = value, best = y;
        if (value > previous) t = 1.0;  // gradient restart (O'Donoghue and Candes)
        previous = value;
        Field next = y;
        for (size_t k = 0; k < next.size(); ++k)
            for (size_t q = 0; q < next[k].size(); ++q)
                next[k][q] = std::clamp(float(y[k][q] - step * gradient[k][q]), lo[k][q], hi[k][q]);
        const double tNext = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * t * t));
        const float momentum = float((t - 1.0) / tNext);
        for (size_t k = 0; k < next.size(); ++k)
            for (size_t q = 0; q < next[k].size(); ++q)
                y[k][q] =
                    std::clamp(next[k][q] + momentum * (next[k][q] - x[k][q]), lo[k][q], hi[k][q]);
        x = std::move(next);
        t = tNext;
        ++out.iterations;
        progress.advance();
    }
    const double last = objective.value(x);
    if (last < bestValue) bestValue = last, best = x;
    out.objectiveXy = bestValue;
    out.contourErrorColumns = objective.contourError(columns->dose);
    out.contourErrorXy = objective.contourError(best);
    out.doses = *columns;
    out.doses.dose = std::move(best);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const DlpBlurOperator& op = objective.blur();
    out.peakFieldMiB =
        4.0 * double(part.layers.size()) * op.cellsX() * op.cellsY() * 4.5 / double(1 << 20);
    return out;
}

}  // namespace vpsim::optimise
