// planInverseShape (inverse_shape.h): dots, the warm start and FISTA over all layers at once.
#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/optimise/laser/inverse_shape.h"

namespace vpsim::optimise {
namespace {

using exposure::ExposureField;
using exposure::SurfaceGrid;

/// Dots of one layer: every stride-th cell centre within half a dot pitch of the region.
std::vector<size_t> layerDots(const geometry::PolygonSet& region, const exposure::ExposureGrid& g,
                              int stride, double dotPitch) {
    std::vector<size_t> dots;
    if (region.empty()) return dots;
    const std::vector<char> allowed = insideMask(region.offset(0.5 * dotPitch), g.surface());
    for (int j = stride / 2; j < g.ny; j += stride)
        for (int i = stride / 2; i < g.nx; i += stride)
            if (allowed[size_t(j) * g.nx + i]) dots.push_back(size_t(j) * g.nx + i);
    return dots;
}

/// The deposit gathered onto the nearest dot (energy outside the dots' area is dropped).
void gather(const SurfaceGrid& deposit, const std::vector<size_t>& dots, int stride,
            double cellArea, double* x) {
    const int nx = deposit.nx, ny = deposit.ny;
    std::vector<long> dotOf(deposit.values.size(), -1);
    for (size_t d = 0; d < dots.size(); ++d) dotOf[dots[d]] = long(d);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const float v = deposit.values[size_t(j) * nx + i];
            if (v == 0) continue;
            const int di = std::min(i / stride * stride + stride / 2, nx - 1);
            const int dj = std::min(j / stride * stride + stride / 2, ny - 1);
            const long d = dotOf[size_t(dj) * nx + di];
            if (d >= 0) x[d] += v * cellArea;
        }
}

void combine(ExposureField& out, const ExposureField& a, const ExposureField& b, double beta) {
    for (size_t v = 0; v < out.size(); ++v)
        for (size_t c = 0; c < out[v].values.size(); ++c)
            out[v].values[c] = float(a[v].values[c] + beta * (a[v].values[c] - b[v].values[c]));
}

/// FISTA with projection onto x >= 0 and a restart whenever J rises; one forward and one
/// adjoint of the stack per iteration (the field of the momentum point is combined from the
/// iterates' fields, the map being linear). Returns the best iterate.
std::vector<double> solve(const ShapeProblem& problem, std::vector<double> x, int iterations,
                          double& best, int& done) {
    const double step = 1.0 / problem.lipschitz();
    ExposureField ax = problem.field(x);
    double fx = problem.valueAt(ax, nullptr);
    best = fx;
    std::vector<double> bestX = x, y = x, xn(x.size()), g;
    ExposureField ay = ax;
    double t = 1;
    for (done = 0; done < iterations; ++done) {
        problem.valueAt(ay, &g);
        for (size_t k = 0; k < x.size(); ++k) xn[k] = std::max(y[k] - step * g[k], 0.0);
        ExposureField axn = problem.field(xn);
        const double fn = problem.valueAt(axn, nullptr);
        if (fn > fx) {  // momentum overshot: restart from x with a plain projected step
            t = 1;
            y = x;
            ay = ax;
            continue;
        }
        if (fn < best) best = fn, bestX = xn;
        const double tn = 0.5 * (1 + std::sqrt(1 + 4 * t * t)), beta = (t - 1) / tn;
        for (size_t k = 0; k < x.size(); ++k) y[k] = xn[k] + beta * (xn[k] - x[k]);
        combine(ay, axn, ax, beta);
        x.swap(xn);
        ax = std::move(axn);
        fx = fn;
        t = tn;
    }
    return bestX;
}

}  // namespace

ShapeResult planInverseShape(const std::vector<geometry::PolygonSet>& regions,
                             const std::vector<geometry::PolygonSet>& sliceRegions,
                             const plan::ScanPlan& start, double gridPitch, double dotPitch,
                             const ShapeParameters& p, const kernel::FittedBeam& beam,
                             double layerThickness, double criticalDose) {
    if (regions.size() != start.layers.size())
        throw InputError("inverse planner: one start layer per region is needed");
    if (!(gridPitch > 0) || !(dotPitch > 0) || p.iterations < 0 || p.slicesPerLayer < 1)
        throw InputError("inverse planner: pitches and slices must be positive, iterations >= 0");
    exposure::ExposureGrid grid = planningGrid(regions, beam.radius, gridPitch);
    grid.slicesPerLayer = p.slicesPerLayer;
    exposure::ExposureEngine model(grid, beam, layerThickness);
    ShapeTargets targets = shapeTargets(grid, layerThickness, beam.attenuationLength,
                                        sliceRegions, criticalDose, p);
    const int stride = std::max(1, int(std::lround(dotPitch / gridPitch)));
    std::vector<std::vector<size_t>> dots;
    for (const auto& r : regions) dots.push_back(layerDots(r, grid, stride, dotPitch));
    ShapeProblem problem(model, targets, dots);

    std::vector<SurfaceGrid> startDeposits(regions.size(), grid.surface());
    for (size_t k = 0; k < regions.size(); ++k)
        exposure::depositLayer(start.layers[k], startDeposits[k]);
    // Ebar: the start's mean exposure inside the part (the uniformity term's level).
    const ExposureField startField = model.stack(startDeposits);
    double sum = 0, count = 0;
    for (size_t v = 0; v < startField.size(); ++v)
        for (size_t c = 0; c < startField[v].values.size(); ++c)
            if (targets.inside[v][c]) sum += startField[v].values[c], count += 1;
    targets.meanInside = count > 0 ? sum / count : criticalDose;

    ShapeResult result;
    result.objectiveStart = shapeObjective(targets, startField);
    std::vector<double> x(problem.size(), 0.0);
    const double cellArea = grid.pitch * grid.pitch;
    for (size_t k = 0, offset = 0; k < regions.size(); offset += dots[k].size(), ++k)
        gather(startDeposits[k], dots[k], stride, cellArea, x.data() + offset);
    result.dots = problem.size();
    result.objectiveDots = problem.value(x);
    double best = result.objectiveDots;
    if (problem.size() > 0) x = solve(problem, x, p.iterations, best, result.iterations);
    if (!(best < result.objectiveStart)) {
        result.plan = start;
        result.keptStart = true;
        result.objectiveFinal = result.objectiveStart;
        return result;
    }
    result.plan = start;
    for (size_t k = 0, offset = 0; k < regions.size(); offset += dots[k].size(), ++k) {
        plan::LayerPlan& layer = result.plan.layers[k];
        layer.vectors.clear();
        layer.points.clear();
        for (size_t d = 0; d < dots[k].size(); ++d)
            if (x[offset + d] > 0)
                layer.points.push_back({grid.originX + (dots[k][d] % grid.nx + 0.5) * grid.pitch,
                                        grid.originY + (dots[k][d] / grid.nx + 0.5) * grid.pitch,
                                        x[offset + d]});
    }
    // Measured on the returned plan (its points deposited as the simulation deposits them).
    std::vector<SurfaceGrid> finalDeposits(regions.size(), grid.surface());
    for (size_t k = 0; k < regions.size(); ++k)
        exposure::depositLayer(result.plan.layers[k], finalDeposits[k]);
    result.objectiveFinal = problem.valueOfDeposits(finalDeposits);
    if (!(result.objectiveFinal < result.objectiveStart)) {
        result.plan = start;
        result.keptStart = true;
        result.objectiveFinal = result.objectiveStart;
    }
    return result;
}

}  // namespace vpsim::optimise
