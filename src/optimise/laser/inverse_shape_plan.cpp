// planInverseShape (inverse_shape.h): dots, the warm start and FISTA over all layers at once.
#include <algorithm>
#include <cmath>
#include <memory>

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

/// The deposit gathered bilinearly onto the dot lattice (every stride-th cell from stride / 2),
/// which keeps each cell's centre of energy (a border loop is not snapped by up to half a dot
/// pitch); the share of a lattice point that is not a dot is dropped.
void gather(const SurfaceGrid& deposit, const std::vector<size_t>& dots, int stride,
            double cellArea, double* x) {
    const int nx = deposit.nx, ny = deposit.ny, first = stride / 2;
    std::vector<long> dotOf(deposit.values.size(), -1);
    for (size_t d = 0; d < dots.size(); ++d) dotOf[dots[d]] = long(d);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const float v = deposit.values[size_t(j) * nx + i];
            if (v == 0) continue;
            const double fx = double(i - first) / stride, fy = double(j - first) / stride;
            const int mx = int(std::floor(fx)), my = int(std::floor(fy));
            const double tx = fx - mx, ty = fy - my;
            for (int b = 0; b < 2; ++b)
                for (int a = 0; a < 2; ++a) {
                    const int di = first + (mx + a) * stride, dj = first + (my + b) * stride;
                    if (di < 0 || dj < 0 || di >= nx || dj >= ny) continue;
                    const long d = dotOf[size_t(dj) * nx + di];
                    const double w = (a ? tx : 1 - tx) * (b ? ty : 1 - ty);
                    if (d >= 0 && w > 0) x[d] += w * v * cellArea;
                }
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
    std::vector<double> step = problem.rowSums();
    for (double& s : step) s = 1.0 / s;
    ExposureField ax = problem.field(x);
    double fx = problem.valueAt(ax, nullptr);
    best = fx;
    std::vector<double> bestX = x, y = x, xn(x.size()), g;
    ExposureField ay = ax;
    double t = 1;
    for (done = 0; done < iterations; ++done) {
        problem.valueAt(ay, &g);
        for (size_t k = 0; k < x.size(); ++k) xn[k] = std::max(y[k] - step[k] * g[k], 0.0);
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

/// One resolution of the problem: the engine, the targets levelled on the start, the dots.
struct ShapeLevel {
    exposure::ExposureGrid grid;
    std::unique_ptr<exposure::ExposureEngine> model;
    ShapeTargets targets;
    std::unique_ptr<ShapeProblem> problem;
    double startObjective = 0;  ///< J of the start plan on this grid
};

std::unique_ptr<ShapeLevel> makeLevel(const exposure::ExposureGrid& grid,
                                      std::vector<std::vector<size_t>> dots,
                                      const std::vector<geometry::PolygonSet>& sliceRegions,
                                      const plan::ScanPlan& start, const ShapeParameters& p,
                                      const kernel::FittedBeam& beam, double layerThickness,
                                      double criticalDose, std::vector<SurfaceGrid>& deposits) {
    auto level = std::make_unique<ShapeLevel>();
    level->grid = grid;
    level->model = std::make_unique<exposure::ExposureEngine>(grid, beam, layerThickness);
    level->targets =
        shapeTargets(grid, layerThickness, beam.attenuationLength, sliceRegions, criticalDose, p);
    deposits.assign(start.layers.size(), grid.surface());
    for (size_t k = 0; k < start.layers.size(); ++k)
        exposure::depositLayer(start.layers[k], deposits[k]);
    const ExposureField startField = level->model->stack(deposits);
    levelTargets(level->targets, startField);
    level->startObjective = shapeObjective(level->targets, startField);
    level->problem = std::make_unique<ShapeProblem>(*level->model, level->targets, std::move(dots));
    return level;
}

/// The grid whose cell centres are the dot cells of `fine` (every stride-th cell from
/// stride / 2), with `fine`'s slices.
exposure::ExposureGrid coarseGrid(const exposure::ExposureGrid& fine, int stride) {
    exposure::ExposureGrid c = fine;
    const int first = stride / 2;
    c.nx = (fine.nx - first + stride - 1) / stride;
    c.ny = (fine.ny - first + stride - 1) / stride;
    c.pitch = fine.pitch * stride;
    const double shift = (first + 0.5 - 0.5 * stride) * fine.pitch;
    c.originX = fine.originX + shift;
    c.originY = fine.originY + shift;
    return c;
}

/// The plan of the dot energies x: the start's layers (their z) with points only.
plan::ScanPlan dotPlan(const plan::ScanPlan& start, const ShapeProblem& problem,
                       const exposure::ExposureGrid& grid, const std::vector<double>& x) {
    plan::ScanPlan out = start;
    const auto& dots = problem.dots();
    for (size_t k = 0, offset = 0; k < dots.size(); offset += dots[k].size(), ++k) {
        plan::LayerPlan& layer = out.layers[k];
        layer.vectors.clear();
        layer.points.clear();
        for (size_t d = 0; d < dots[k].size(); ++d)
            if (x[offset + d] > 0)
                layer.points.push_back({grid.originX + (dots[k][d] % grid.nx + 0.5) * grid.pitch,
                                        grid.originY + (dots[k][d] / grid.nx + 0.5) * grid.pitch,
                                        x[offset + d]});
    }
    return out;
}

}  // namespace

ShapeResult planInverseShape(const std::vector<geometry::PolygonSet>& regions,
                             const std::vector<geometry::PolygonSet>& sliceRegions,
                             const plan::ScanPlan& start, double gridPitch, double dotPitch,
                             const ShapeParameters& p, const kernel::FittedBeam& beam,
                             double layerThickness, double criticalDose) {
    if (regions.size() != start.layers.size())
        throw InputError("inverse planner: one start layer per region is needed");
    if (!(gridPitch > 0) || !(dotPitch > 0) || p.iterations < 0 || p.coarseIterations < 0 ||
        p.slicesPerLayer < 1)
        throw InputError("inverse planner: pitches and slices must be positive, iterations >= 0");
    exposure::ExposureGrid grid = planningGrid(regions, beam.radius, gridPitch);
    grid.slicesPerLayer = p.slicesPerLayer;
    const int stride = std::max(1, int(std::lround(dotPitch / gridPitch)));
    std::vector<std::vector<size_t>> dots;
    for (const auto& r : regions) dots.push_back(layerDots(r, grid, stride, dotPitch));
    std::vector<SurfaceGrid> deposits;
    auto fine =
        makeLevel(grid, dots, sliceRegions, start, p, beam, layerThickness, criticalDose, deposits);
    const ShapeProblem& problem = *fine->problem;

    ShapeResult result;
    result.objectiveStart = fine->startObjective;
    std::vector<double> x(problem.size(), 0.0);
    const double cellArea = grid.pitch * grid.pitch;
    for (size_t k = 0, offset = 0; k < regions.size(); offset += dots[k].size(), ++k)
        gather(deposits[k], dots[k], stride, cellArea, x.data() + offset);
    result.dots = problem.size();
    result.objectiveDots = problem.value(x);
    double best = result.objectiveDots;
    int done = 0;
    // First on the grid whose cells are the dots: the same variables, stride^2 fewer cells and
    // a stride times shorter blur (the engine needs We3D >= its pitch).
    if (stride > 1 && p.coarseIterations > 0 && beam.radius >= gridPitch * stride &&
        problem.size() > 0) {
        const exposure::ExposureGrid cg = coarseGrid(grid, stride);
        std::vector<std::vector<size_t>> coarseDots(dots.size());
        for (size_t k = 0; k < dots.size(); ++k)
            for (size_t c : dots[k])
                coarseDots[k].push_back(size_t((long(c / grid.nx) - stride / 2) / stride) * cg.nx +
                                        size_t((long(c % grid.nx) - stride / 2) / stride));
        std::vector<SurfaceGrid> coarseDeposits;
        auto coarse = makeLevel(cg, std::move(coarseDots), sliceRegions, start, p, beam,
                                layerThickness, criticalDose, coarseDeposits);
        x = solve(*coarse->problem, x, p.coarseIterations, best, done);
        result.iterations += done;
    }
    if (problem.size() > 0) x = solve(problem, x, p.iterations, best, done);
    result.iterations += done;
    result.plan = start;
    result.keptStart = true;
    result.objectiveFinal = result.objectiveStart;
    if (!(best < result.objectiveStart)) return result;
    // Measured on the returned plan (its points deposited as the simulation deposits them).
    plan::ScanPlan planned = dotPlan(start, problem, grid, x);
    std::vector<SurfaceGrid> finalDeposits(regions.size(), grid.surface());
    for (size_t k = 0; k < regions.size(); ++k)
        exposure::depositLayer(planned.layers[k], finalDeposits[k]);
    const double final = problem.valueOfDeposits(finalDeposits);
    if (final < result.objectiveStart) {
        result.plan = std::move(planned);
        result.keptStart = false;
        result.objectiveFinal = final;
    }
    return result;
}

}  // namespace vpsim::optimise
