// planInverseShape (inverse_shape.h): dots, the warm start and FISTA over all layers at once.
#include <algorithm>
#include <cmath>
#include <memory>

#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/optimise/laser/inverse_shape.h"
#include "vpsim/optimise/solvers/projected_fista.h"

namespace vpsim::optimise {
namespace {

using exposure::ExposureField;
using exposure::SurfaceGrid;

/// Where one layer's dots lie on the planning grid: every `stride`-th cell from stride / 2 along
/// its rows, and every `rowStride`-th from `firstRow` across them (rows along x or y).
struct Lattice {
    int stride = 1, rowStride = 1, firstRow = 0;
    bool alongX = true;
    int strideX() const { return alongX ? stride : rowStride; }
    int strideY() const { return alongX ? rowStride : stride; }
    int firstX() const { return alongX ? stride / 2 : firstRow; }
    int firstY() const { return alongX ? firstRow : stride / 2; }
};

/// The lattice cells of `allowed` (and not `deep`).
std::vector<size_t> latticeCells(const std::vector<char>& allowed, const std::vector<char>& deep,
                                 const exposure::ExposureGrid& g, const Lattice& lattice) {
    std::vector<size_t> dots;
    for (int j = lattice.firstY(); j < g.ny; j += lattice.strideY())
        for (int i = lattice.firstX(); i < g.nx; i += lattice.strideX()) {
            const size_t c = size_t(j) * g.nx + i;
            if (allowed[c] && !deep[c]) dots.push_back(c);
        }
    return dots;
}

/// Runs of neighbouring dots along the lattice's rows: each is a scan line on the machine.
size_t rowRuns(const std::vector<size_t>& dots, const exposure::ExposureGrid& g,
               const Lattice& lattice) {
    size_t runs = 0;
    for (size_t d = 0; d < dots.size(); ++d) {
        const size_t next = lattice.alongX ? dots[d - (d > 0)] + size_t(lattice.stride)
                                           : dots[d - (d > 0)] + size_t(lattice.stride) * g.nx;
        runs += d == 0 || dots[d] != next;
    }
    return runs;
}

/// Dots of one layer: the lattice cells within half a dot pitch of the region (with an edge band,
/// not deeper inside than the band; half a row spacing, letting a row just outside a wall along
/// it carry the wall, lowered laser-tapered's IoU from 0.9757 to 0.9747). Rows `rowEvery` dot
/// pitches apart lie along x or y, whichever gives fewer scan lines (by layer parity where both
/// give about as many); odd layers' rows lie half way
/// between even layers' (`staggered`), so that across two layers a wall along the rows meets rows
/// at about the dot pitch.
std::vector<size_t> layerDots(const geometry::PolygonSet& region, const exposure::ExposureGrid& g,
                              int stride, int rowEvery, bool staggered, double edgeBand,
                              Lattice& lattice) {
    lattice = {stride, stride * rowEvery, stride / 2 + (staggered ? stride * (rowEvery / 2) : 0),
               true};
    if (region.empty()) return {};
    const std::vector<char> allowed =
        insideMask(region.offset(0.5 * lattice.stride * g.pitch), g.surface());
    const std::vector<char> deep = edgeBand > 0 ? insideMask(region.offset(-edgeBand), g.surface())
                                                : std::vector<char>(allowed.size(), 0);
    std::vector<size_t> dots = latticeCells(allowed, deep, g, lattice);
    if (rowEvery == 1) return dots;
    Lattice alongY = lattice;
    alongY.alongX = false;
    std::vector<size_t> other = latticeCells(allowed, deep, g, alongY);
    // latticeCells lists by y then x; rows along y are counted in x-then-y order.
    std::vector<size_t> byColumn = other;
    std::sort(byColumn.begin(), byColumn.end(), [&](size_t a, size_t b) {
        return std::make_pair(a % g.nx, a / g.nx) < std::make_pair(b % g.nx, b / g.nx);
    });
    // Within 10% of each other (a square, a disc) the axis alternates from layer to layer, so
    // that every wall meets the dot pitch along the rows every other layer.
    const size_t runsX = rowRuns(dots, g, lattice), runsY = rowRuns(byColumn, g, alongY);
    const bool similar = 10 * std::max(runsX, runsY) <= 11 * std::min(runsX, runsY);
    if (similar ? staggered : runsY < runsX) {
        lattice = alongY;
        return other;
    }
    return dots;
}

/// The start's marks the dots take over (`moving`: every mark without an edge band, else the
/// dots and the vectors whose every point lies within the band of the contour) and the others
/// (`fixed`, held as they are); both keep the start's layers.
void splitStart(const plan::ScanPlan& start, const std::vector<geometry::PolygonSet>& regions,
                double edgeBand, plan::ScanPlan& moving, plan::ScanPlan& fixed) {
    moving = fixed = start;
    for (size_t k = 0; k < start.layers.size(); ++k) {
        plan::LayerPlan &m = moving.layers[k], &f = fixed.layers[k];
        m.vectors.clear(), m.points.clear(), m.trajectory.clear();
        f.vectors.clear(), f.points.clear(), f.trajectory.clear();
        const geometry::PolygonSet deep =
            edgeBand > 0 ? regions[k].offset(-edgeBand) : geometry::PolygonSet();
        auto nearEdge = [&](double x, double y) { return edgeBand <= 0 || !deep.contains({x, y}); };
        for (const plan::LaserVector& v : start.layers[k].vectors) {
            // Sampled every half band: a hatch line across the middle has points deep inside.
            const double length = std::hypot(v.x1 - v.x0, v.y1 - v.y0);
            const int samples = edgeBand > 0 ? 1 + int(std::ceil(2 * length / edgeBand)) : 1;
            bool near = true;
            for (int i = 0; i <= samples && near; ++i) {
                const double t = double(i) / samples;
                near = nearEdge(v.x0 + t * (v.x1 - v.x0), v.y0 + t * (v.y1 - v.y0));
            }
            (near ? m : f).vectors.push_back(v);
        }
        for (const plan::LaserPoint& p : start.layers[k].points)
            (nearEdge(p.x, p.y) ? m : f).points.push_back(p);
    }
}

/// The per-layer deposits of a plan on `grid`.
std::vector<SurfaceGrid> depositsOf(const plan::ScanPlan& plan,
                                    const exposure::ExposureGrid& grid) {
    std::vector<SurfaceGrid> deposits(plan.layers.size(), grid.surface());
    for (size_t k = 0; k < plan.layers.size(); ++k)
        exposure::depositLayer(plan.layers[k], deposits[k]);
    return deposits;
}

/// The deposit gathered bilinearly onto the dot lattice, which keeps each cell's centre of energy
/// (a border loop is not snapped by up to half a dot pitch, a hatch line between two rows is
/// shared by both); the share of a lattice point that is not a dot is dropped.
void gather(const SurfaceGrid& deposit, const std::vector<size_t>& dots, const Lattice& lattice,
            double cellArea, double* x) {
    const int nx = deposit.nx, ny = deposit.ny, sx = lattice.strideX(), sy = lattice.strideY();
    const int firstX = lattice.firstX(), firstY = lattice.firstY();
    std::vector<long> dotOf(deposit.values.size(), -1);
    for (size_t d = 0; d < dots.size(); ++d) dotOf[dots[d]] = long(d);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const float v = deposit.values[size_t(j) * nx + i];
            if (v == 0) continue;
            const double fx = double(i - firstX) / sx, fy = double(j - firstY) / sy;
            const int mx = int(std::floor(fx)), my = int(std::floor(fy));
            const double tx = fx - mx, ty = fy - my;
            for (int b = 0; b < 2; ++b)
                for (int a = 0; a < 2; ++a) {
                    const int di = firstX + (mx + a) * sx, dj = firstY + (my + b) * sy;
                    if (di < 0 || dj < 0 || di >= nx || dj >= ny) continue;
                    const long d = dotOf[size_t(dj) * nx + di];
                    const double w = (a ? tx : 1 - tx) * (b ? ty : 1 - ty);
                    if (d >= 0 && w > 0) x[d] += w * v * cellArea;
                }
        }
}

/// The shape problem as the solver's FISTA sees it (optimise/solvers/projected_fista.h): one
/// forward and one adjoint of the stack per iteration.
struct StackImage {
    const ShapeProblem& problem;
    ExposureField forward(const std::vector<double>& x) const { return problem.field(x); }
    double value(const ExposureField& field) const { return problem.valueAt(field, nullptr); }
    std::vector<double> gradient(const ExposureField& field) const {
        std::vector<double> g;
        problem.valueAt(field, &g);
        return g;
    }
    static void extrapolate(ExposureField& out, const ExposureField& a, const ExposureField& b,
                            double beta) {
        for (size_t v = 0; v < out.size(); ++v)
            for (size_t c = 0; c < out[v].values.size(); ++c)
                out[v].values[c] = float(a[v].values[c] + beta * (a[v].values[c] - b[v].values[c]));
    }
};

/// The best iterate of FISTA in the metric of the Hessian's row sums.
std::vector<double> solve(const ShapeProblem& problem, std::vector<double> x, int iterations,
                          double& best, int& done, Progress& progress) {
    std::vector<double> step = problem.rowSums();
    for (double& s : step) s = 1.0 / s;
    FistaResult r = nonNegativeFista(StackImage{problem}, std::move(x), step, iterations,
                                     [&] { progress.advance(); });
    best = r.best, done = r.iterations;
    return std::move(r.x);
}

/// One resolution of the problem: the engine, the targets levelled on the start, the dots.
struct ShapeLevel {
    exposure::ExposureGrid grid;
    std::unique_ptr<exposure::ExposureEngine> model;
    ShapeTargets targets;
    std::unique_ptr<ShapeProblem> problem;
    double startObjective = 0;  ///< J of the start plan on this grid
};

/// The level on `grid`: the start is `moving` (the marks the dots take over; `deposits` gets
/// their deposits) plus `fixed` (held).
std::unique_ptr<ShapeLevel> makeLevel(const exposure::ExposureGrid& grid,
                                      std::vector<std::vector<size_t>> dots,
                                      const std::vector<geometry::PolygonSet>& sliceRegions,
                                      const plan::ScanPlan& moving, const plan::ScanPlan& fixed,
                                      const ShapeParameters& p, const kernel::FittedBeam& beam,
                                      double layerThickness, double criticalDose,
                                      std::vector<SurfaceGrid>& deposits) {
    auto level = std::make_unique<ShapeLevel>();
    level->grid = grid;
    level->model = std::make_unique<exposure::ExposureEngine>(grid, beam, layerThickness);
    level->targets =
        shapeTargets(grid, layerThickness, beam.attenuationLength, sliceRegions, criticalDose, p);
    deposits = depositsOf(moving, grid);
    std::vector<SurfaceGrid> held = depositsOf(fixed, grid), start = deposits;
    for (size_t k = 0; k < start.size(); ++k)
        for (size_t c = 0; c < start[k].values.size(); ++c) start[k].values[c] += held[k].values[c];
    const ExposureField startField = level->model->stack(start);
    levelTargets(level->targets, startField);
    level->startObjective = shapeObjective(level->targets, startField);
    level->problem = std::make_unique<ShapeProblem>(*level->model, level->targets, std::move(dots));
    if (p.edgeBand > 0) level->problem->holdFixed(std::move(held));
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

/// The plan of the dot energies x added to the fixed marks (none without an edge band).
plan::ScanPlan dotPlan(const plan::ScanPlan& fixed, const ShapeProblem& problem,
                       const exposure::ExposureGrid& grid, const std::vector<double>& x) {
    plan::ScanPlan out = fixed;
    const auto& dots = problem.dots();
    for (size_t k = 0, offset = 0; k < dots.size(); offset += dots[k].size(), ++k) {
        plan::LayerPlan& layer = out.layers[k];
        for (size_t d = 0; d < dots[k].size(); ++d)
            if (x[offset + d] > 0)
                layer.points.push_back({grid.originX + (dots[k][d] % grid.nx + 0.5) * grid.pitch,
                                        grid.originY + (dots[k][d] / grid.nx + 0.5) * grid.pitch,
                                        x[offset + d]});
    }
    return out;
}

}  // namespace

exposure::ExposureGrid shapePlanningGrid(const std::vector<geometry::PolygonSet>& regions,
                                         double beamRadius, double pitch) {
    exposure::ExposureGrid g = planningGrid(regions, beamRadius, pitch);
    g.originX = std::floor(g.originX / g.pitch + 1e-9) * g.pitch;
    g.originY = std::floor(g.originY / g.pitch + 1e-9) * g.pitch;
    g.nx += 1, g.ny += 1;
    return g;
}

ShapeResult planInverseShape(const std::vector<geometry::PolygonSet>& regions,
                             const std::vector<geometry::PolygonSet>& sliceRegions,
                             const plan::ScanPlan& start, double gridPitch, double dotPitch,
                             const ShapeParameters& p, const kernel::FittedBeam& beam,
                             double layerThickness, double criticalDose,
                             const MachineFit& toMachine) {
    if (regions.size() != start.layers.size())
        throw InputError("inverse planner: one start layer per region is needed");
    if (!(gridPitch > 0) || !(dotPitch > 0) || p.iterations < 0 || p.coarseIterations < 0 ||
        p.slicesPerLayer < 1)
        throw InputError("inverse planner: pitches and slices must be positive, iterations >= 0");
    exposure::ExposureGrid grid = shapePlanningGrid(regions, beam.radius, gridPitch);
    grid.slicesPerLayer = p.slicesPerLayer;
    const int stride = std::max(1, int(std::lround(dotPitch / gridPitch)));
    const double pitch = stride * gridPitch;  // the dots' pitch along the rows
    const int rowEvery = std::max(1, int(std::floor(p.rowSpacing / pitch + 1e-6)));
    std::vector<std::vector<size_t>> dots;
    std::vector<Lattice> lattices(regions.size());
    for (size_t k = 0; k < regions.size(); ++k)
        dots.push_back(
            layerDots(regions[k], grid, stride, rowEvery, k % 2 == 1, p.edgeBand, lattices[k]));
    plan::ScanPlan moving, fixed;
    splitStart(start, regions, p.edgeBand, moving, fixed);
    std::vector<SurfaceGrid> deposits;
    auto fine = makeLevel(grid, dots, sliceRegions, moving, fixed, p, beam, layerThickness,
                          criticalDose, deposits);
    const ShapeProblem& problem = *fine->problem;

    ShapeResult result;
    result.objectiveStart = fine->startObjective;
    std::vector<double> x(problem.size(), 0.0);
    const double cellArea = grid.pitch * grid.pitch;
    for (size_t k = 0, offset = 0; k < regions.size(); offset += dots[k].size(), ++k)
        gather(deposits[k], dots[k], lattices[k], cellArea, x.data() + offset);
    result.dots = problem.size();
    result.objectiveDots = problem.value(x);
    double best = result.objectiveDots;
    int done = 0;
    // First on the grid whose cells are the dots: the same variables, stride^2 fewer cells and
    // a stride times shorter blur (the engine needs We3D >= its pitch).
    const bool coarseStage = stride > 1 && p.coarseIterations > 0 &&
                             beam.radius >= gridPitch * stride && problem.size() > 0;
    Progress progress("inverse planner: shape objective iterations",
                      problem.size() > 0
                          ? uint64_t(coarseStage ? p.coarseIterations : 0) + uint64_t(p.iterations)
                          : 0);
    if (coarseStage) {
        const exposure::ExposureGrid cg = coarseGrid(grid, stride);
        std::vector<std::vector<size_t>> coarseDots(dots.size());
        for (size_t k = 0; k < dots.size(); ++k)
            for (size_t c : dots[k])
                coarseDots[k].push_back(size_t((long(c / grid.nx) - stride / 2) / stride) * cg.nx +
                                        size_t((long(c % grid.nx) - stride / 2) / stride));
        std::vector<SurfaceGrid> coarseDeposits;
        auto coarse = makeLevel(cg, std::move(coarseDots), sliceRegions, moving, fixed, p, beam,
                                layerThickness, criticalDose, coarseDeposits);
        x = solve(*coarse->problem, x, p.coarseIterations, best, done, progress);
        result.iterations += done;
    }
    if (problem.size() > 0) x = solve(problem, x, p.iterations, best, done, progress);
    progress.finish();
    result.iterations += done;
    result.plan = start;
    result.keptStart = true;
    result.objectiveFinal = result.objectiveStart;
    if (!(best < result.objectiveStart)) return result;
    // Measured on the returned plan as the machine runs it (its marks deposited as the
    // simulation deposits them).
    plan::ScanPlan planned = dotPlan(fixed, problem, grid, x);
    if (toMachine) toMachine(planned);
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
