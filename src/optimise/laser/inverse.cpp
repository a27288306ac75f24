#include "vpsim/optimise/laser/inverse.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/optimise/solvers/projected_fista.h"
#include "vpsim/plan/feature_blocks.h"

namespace vpsim::optimise {
namespace {

using exposure::SurfaceGrid;

/// One layer's least-squares problem f(x) = 1/2 |W (M S x + offset)|^2 (see the header).
struct LayerProblem {
    exposure::ExposureModel* model = nullptr;
    std::vector<size_t> dots;   ///< dot cells
    std::vector<char> counted;  ///< cells in the objective
    std::vector<float> offset;  ///< E_t - Etm on counted cells
    double cellArea = 0;

    SurfaceGrid forward(const std::vector<double>& x) const {
        SurfaceGrid deposit = model->grid().surface();
        for (size_t k = 0; k < dots.size(); ++k) deposit.values[dots[k]] = float(x[k] / cellArea);
        return model->layerMap(deposit, 0.0);
    }
    double value(const SurfaceGrid& map) const {
        double sum = 0;
        for (size_t c = 0; c < counted.size(); ++c)
            if (counted[c]) {
                double r = map.values[c] + offset[c];
                sum += r * r;
            }
        return 0.5 * sum;
    }
    std::vector<double> gradient(const SurfaceGrid& map) const {
        SurfaceGrid r = model->grid().surface();
        for (size_t c = 0; c < counted.size(); ++c)
            if (counted[c]) r.values[c] = map.values[c] + offset[c];
        SurfaceGrid back = model->layerMapAdjoint(r, 0.0);
        std::vector<double> g(dots.size());
        for (size_t k = 0; k < dots.size(); ++k) g[k] = back.values[dots[k]] / cellArea;
        return g;
    }
    /// An upper bound of the largest eigenvalue of S'M'WMS: the matrix is non-negative (a
    /// positive kernel, a 0/1 mask), so its spectral radius is at most its largest row sum, the
    /// largest entry of S'M'WMS 1 (two maps, where a power iteration takes many; tight to a few
    /// per cent on a part much wider than the beam).
    double lipschitz() const {
        SurfaceGrid map = forward(std::vector<double>(dots.size(), 1.0));
        for (size_t c = 0; c < counted.size(); ++c)
            if (!counted[c]) map.values[c] = 0;
        SurfaceGrid back = model->layerMapAdjoint(map, 0.0);
        double largest = 0;
        for (size_t d : dots) largest = std::max(largest, double(back.values[d]) / cellArea);
        return 1.001 * std::max(largest, 1e-300);  // float rounding of the maps
    }
    static void extrapolate(SurfaceGrid& out, const SurfaceGrid& a, const SurfaceGrid& b,
                            double beta) {
        for (size_t c = 0; c < out.values.size(); ++c)
            out.values[c] = float(a.values[c] + beta * (a.values[c] - b.values[c]));
    }
};

/// The best iterate of the solver's FISTA (optimise/solvers/projected_fista.h) at 1 / L.
std::vector<double> solve(const LayerProblem& problem, std::vector<double> x, int iterations,
                          double& best, int& done) {
    const std::vector<double> step(x.size(), 1.0 / problem.lipschitz());
    FistaResult r = nonNegativeFista(problem, std::move(x), step, iterations);
    best = r.best, done = r.iterations;
    return std::move(r.x);
}

/// A grid whose cell centres are the dot cells of `fine` (every stride-th cell from stride/2):
/// the coarse stage solves the same dots on it, with maps stride^2 times smaller.
struct CoarseGrid {
    exposure::ExposureGrid grid;
    int stride = 1, first = 0;
    size_t cellOf(size_t fineCell, int fineNx) const {
        return size_t((long(fineCell / fineNx) - first) / stride) * grid.nx +
               size_t((long(fineCell % fineNx) - first) / stride);
    }
};

CoarseGrid coarseGrid(const exposure::ExposureGrid& fine, int stride) {
    CoarseGrid c;
    c.stride = stride;
    c.first = stride / 2;
    c.grid = fine;
    c.grid.nx = (fine.nx - c.first + stride - 1) / stride;
    c.grid.ny = (fine.ny - c.first + stride - 1) / stride;
    c.grid.pitch = fine.pitch * stride;
    const double shift = (c.first + 0.5 - 0.5 * stride) * fine.pitch;
    c.grid.originX = fine.originX + shift;
    c.grid.originY = fine.originY + shift;
    return c;
}

/// What one layer's problem needs besides the grid: its region, Etar, the target's wall shift
/// and the exposure the layers above transmit (on the fine grid).
struct LayerInputs {
    const geometry::PolygonSet* region = nullptr;
    double etar = 0, wallShift = 0, band = 0, criticalDose = 0;
    const SurfaceGrid* transmitted = nullptr;
};

/// The problem on `model`'s grid: counted cells (the part plus Reff), the offset E_t - Etm
/// (E_t sampled at the cells' centres through `sample`), no dots yet.
template <typename Sample>
LayerProblem problemOn(exposure::ExposureModel& model, const LayerInputs& in, Sample sample) {
    LayerProblem problem;
    problem.model = &model;
    problem.cellArea = model.grid().pitch * model.grid().pitch;
    const SurfaceGrid surface = model.grid().surface();
    problem.counted = insideMask(in.region->offset(in.band), surface);
    const std::vector<char> inside = insideMask(in.region->offset(in.wallShift), surface);
    problem.offset.resize(inside.size());
    for (size_t c = 0; c < inside.size(); ++c)
        problem.offset[c] = float(sample(c) - (inside[c] ? in.etar : 0.0));
    return problem;
}

/// Where the transmitted exposure exceeds what the layer may receive (reports).
LayerCompensation compensationOf(const LayerProblem& fine, const LayerInputs& in) {
    LayerCompensation rec;
    const std::vector<float>& t = in.transmitted->values;
    for (size_t c = 0; c < t.size(); ++c) {
        const double excess = fine.offset[c], target = t[c] - excess;
        if (excess > 0.05 * in.etar) rec.uncompensableArea += fine.cellArea;
        rec.uncompensableMax = std::max(rec.uncompensableMax, excess / in.etar);
        if (target == 0 && t[c] >= in.criticalDose) rec.curingOutsideArea += fine.cellArea;
        rec.compensated |= target > 0 && t[c] > 0.01 * in.etar;
    }
    return rec;
}

/// Dots on every stride-th cell centre within half a dot pitch of the region, and the ACES
/// deposit gathered onto the nearest dot (the warm start).
std::vector<double> placeDots(LayerProblem& problem, const geometry::PolygonSet& region,
                              const SurfaceGrid& acesDeposit, int stride, double dotPitch) {
    const exposure::ExposureGrid& grid = problem.model->grid();
    const std::vector<char> allowed = insideMask(region.offset(0.5 * dotPitch), acesDeposit);
    std::vector<long> dotOf(allowed.size(), -1);
    for (int j = stride / 2; j < grid.ny; j += stride)
        for (int i = stride / 2; i < grid.nx; i += stride) {
            size_t c = size_t(j) * grid.nx + i;
            if (!allowed[c]) continue;
            dotOf[c] = long(problem.dots.size());
            problem.dots.push_back(c);
        }
    std::vector<double> x(problem.dots.size(), 0.0);
    for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i) {
            float v = acesDeposit.values[size_t(j) * grid.nx + i];
            if (v == 0) continue;
            int di = std::min(i / stride * stride + stride / 2, grid.nx - 1);
            int dj = std::min(j / stride * stride + stride / 2, grid.ny - 1);
            long d = dotOf[size_t(dj) * grid.nx + di];
            if (d >= 0) x[d] += v * problem.cellArea;
        }
    return x;
}

/// The planner's state across layers (planned top down).
struct InverseRun {
    const InverseParameters& ip;
    const kernel::FittedBeam& beam;
    exposure::ExposureModel& model;
    std::unique_ptr<exposure::ExposureModel> coarseModel;  ///< null: no coarse stage
    CoarseGrid coarse;
    int stride = 1;
    std::vector<SurfaceGrid> deposits;  ///< planned layers' deposits, bottom first
};

/// Plans layer k into `layer`, filling its report and compensation record.
void planLayer(InverseRun& run, const geometry::PolygonSet& region, int k, double top,
               plan::LayerPlan& layer, InverseLayerReport& rep, LayerCompensation& rec,
               double& targetDose) {
    const DfbtpParameters& p = run.ip.base;
    const exposure::ExposureGrid& grid = run.model.grid();
    SurfaceGrid transmitted = grid.surface();
    if (p.compensate)
        transmitted = transmittedExposure(run.model, run.deposits, k, run.beam.attenuationLength);
    const plan::AcesDesign design = plan::designAces(p.aces, region);
    const double reff = plan::effectiveRadius(run.beam.radius);
    LayerInputs in{&region,
                   design.targetDose * run.beam.efficiency,
                   p.wallOnContour ? targetWallShift(p.aces, design.targetDose) : 0.0,
                   reff,
                   p.aces.criticalDose * run.beam.efficiency,
                   &transmitted};
    targetDose = in.etar;
    const plan::LayerPlan aces = plan::planAcesLayer(region, design, p.aces.laserPower, top);
    LayerProblem fine = problemOn(run.model, in, [&](size_t c) { return transmitted.values[c]; });
    rec = compensationOf(fine, in);
    SurfaceGrid acesDeposit = grid.surface();
    exposure::depositLayer(aces, acesDeposit);
    std::vector<double> x = placeDots(fine, region, acesDeposit, run.stride, run.ip.dotPitch);
    rep.dots = int(fine.dots.size());
    rep.acesObjective = fine.value(run.model.layerMap(acesDeposit, 0.0));
    rep.startObjective = fine.value(fine.forward(x));
    double best = 0;
    int done = 0;
    if (run.coarseModel && !x.empty()) {  // the same dots on the coarse grid first
        LayerProblem coarse = problemOn(*run.coarseModel, in, [&](size_t c) {
            size_t i = c % run.coarse.grid.nx, j = c / run.coarse.grid.nx;
            return transmitted.values[(run.coarse.first + j * run.stride) * grid.nx +
                                      run.coarse.first + i * run.stride];
        });
        for (size_t d : fine.dots) coarse.dots.push_back(run.coarse.cellOf(d, grid.nx));
        x = solve(coarse, x, run.ip.coarseIterations, best, done);
    }
    std::vector<double> solution = solve(fine, x, run.ip.iterations, best, rep.iterations);
    if (!(best < rep.acesObjective)) {
        layer = aces;
        rep.keptAces = true;
        rep.finalObjective = rep.acesObjective;
        return;
    }
    rep.finalObjective = best;
    for (size_t d = 0; d < solution.size(); ++d)
        if (solution[d] > 0)
            layer.points.push_back({grid.originX + (fine.dots[d] % grid.nx + 0.5) * grid.pitch,
                                    grid.originY + (fine.dots[d] / grid.nx + 0.5) * grid.pitch,
                                    solution[d]});
}

}  // namespace

InverseResult planInverse(const std::vector<geometry::PolygonSet>& regions,
                          const std::vector<double>& tops, const InverseParameters& ip,
                          const kernel::FittedBeam& beam, exposure::ExposureModel* model) {
    const DfbtpParameters& p = ip.base;
    if (regions.size() != tops.size())
        throw InputError("inverse planner: one top height per layer region is needed");
    if (!(ip.dotPitch > 0) || ip.iterations < 0 || ip.coarseIterations < 0 || !(p.gridPitch > 0))
        throw InputError("inverse planner: dot and grid pitch must be positive, iterations >= 0");
    std::unique_ptr<exposure::ExposureModel> own;
    if (!model) {
        own = std::make_unique<exposure::ExposureEngine>(
            planningGrid(regions, beam.radius, p.gridPitch), beam, p.aces.layerThickness);
        model = own.get();
    }
    InverseRun run{ip, beam, *model, nullptr, {}, 1, {}};
    run.stride = std::max(1, int(std::lround(ip.dotPitch / model->grid().pitch)));
    // The coarse stage needs the fitted engine at the dot pitch (only when planInverse owns it:
    // a caller's model may be another one) and a beam wider than the dot pitch.
    if (own && run.stride > 1 && ip.coarseIterations > 0 && beam.radius >= ip.dotPitch) {
        run.coarse = coarseGrid(model->grid(), run.stride);
        run.coarseModel = std::make_unique<exposure::ExposureEngine>(run.coarse.grid, beam,
                                                                     p.aces.layerThickness);
    }
    run.deposits.assign(regions.size(), model->grid().surface());
    InverseResult result;
    result.plan.machine.layerThickness = p.aces.layerThickness;
    result.plan.machine.laserPower = p.aces.laserPower;
    result.plan.machine.beamRadius = beam.radius;
    result.plan.layers.resize(regions.size());
    result.layers.resize(regions.size());
    result.compensation.resize(regions.size());
    Progress progress("inverse planner: layers", regions.size());
    for (int k = int(regions.size()) - 1; k >= 0; --k, progress.advance()) {
        plan::LayerPlan& layer = result.plan.layers[k];
        layer.z = tops[k];
        if (regions[k].empty()) continue;
        planLayer(run, regions[k], k, tops[k], layer, result.layers[k], result.compensation[k],
                  result.targetDose);
        exposure::depositLayer(layer, run.deposits[k]);
    }
    return result;
}

}  // namespace vpsim::optimise
