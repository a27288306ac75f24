#include "vpsim/optimise/inverse_planner.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "vpsim/core/error.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/dfbtp_exposure_error.h"
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
    /// Largest eigenvalue of S'M'WMS by power iteration from the all-ones vector (8 steps: the
    /// operator is positive, so it converges fast; +10% margin for the rest).
    double lipschitz() const {
        std::vector<double> v(dots.size(), 1.0);
        double lambda = 0;
        for (int it = 0; it < 8; ++it) {
            SurfaceGrid map = forward(v);
            for (size_t c = 0; c < counted.size(); ++c)
                if (!counted[c]) map.values[c] = 0;
            SurfaceGrid back = model->layerMapAdjoint(map, 0.0);
            double norm = 0, vnorm = 0;
            std::vector<double> w(dots.size());
            for (size_t k = 0; k < dots.size(); ++k) {
                w[k] = back.values[dots[k]] / cellArea;
                norm += w[k] * w[k];
                vnorm += v[k] * v[k];
            }
            lambda = std::sqrt(norm / std::max(vnorm, 1e-300));
            double scale = 1.0 / std::sqrt(std::max(norm, 1e-300));
            for (size_t k = 0; k < dots.size(); ++k) v[k] = w[k] * scale;
        }
        return 1.1 * lambda;
    }
};

/// FISTA with projection onto x >= 0 and a restart whenever f rises. Returns the best iterate.
std::vector<double> solve(const LayerProblem& problem, std::vector<double> x, int iterations,
                          double& best, int& done) {
    const double step = 1.0 / problem.lipschitz();
    SurfaceGrid ax = problem.forward(x);
    double fx = problem.value(ax);
    best = fx;
    std::vector<double> bestX = x, y = x, xn(x.size());
    SurfaceGrid ay = ax;
    double t = 1;
    for (done = 0; done < iterations; ++done) {
        std::vector<double> g = problem.gradient(ay);
        for (size_t k = 0; k < x.size(); ++k) xn[k] = std::max(y[k] - step * g[k], 0.0);
        SurfaceGrid axn = problem.forward(xn);
        double fn = problem.value(axn);
        if (fn > fx) {  // momentum overshot: restart from x with a plain projected step
            t = 1;
            y = x;
            ay = ax;
            continue;
        }
        if (fn < best) best = fn, bestX = xn;
        double tn = 0.5 * (1 + std::sqrt(1 + 4 * t * t)), beta = (t - 1) / tn;
        for (size_t k = 0; k < x.size(); ++k) y[k] = xn[k] + beta * (xn[k] - x[k]);
        for (size_t c = 0; c < ay.values.size(); ++c)
            ay.values[c] = float(axn.values[c] + beta * (axn.values[c] - ax.values[c]));
        x.swap(xn);
        ax = std::move(axn);
        fx = fn;
        t = tn;
    }
    return bestX;
}

}  // namespace

InverseResult planInverse(const std::vector<geometry::PolygonSet>& regions,
                          const std::vector<double>& tops, const InverseParameters& ip,
                          const kernel::FittedBeam& beam, exposure::ExposureModel* model) {
    const DfbtpParameters& p = ip.base;
    if (regions.size() != tops.size())
        throw InputError("inverse planner: one top height per layer region is needed");
    if (!(ip.dotPitch > 0) || ip.iterations < 0 || !(p.gridPitch > 0))
        throw InputError("inverse planner: dot and grid pitch must be positive, iterations >= 0");
    std::unique_ptr<exposure::ExposureModel> own;
    if (!model) {
        own = std::make_unique<exposure::ExposureEngine>(
            planningGrid(regions, beam.radius, p.gridPitch), beam, p.aces.layerThickness);
        model = own.get();
    }
    const exposure::ExposureGrid& grid = model->grid();
    const int stride = std::max(1, int(std::lround(ip.dotPitch / grid.pitch)));
    const double reff = plan::effectiveRadius(beam.radius), cellArea = grid.pitch * grid.pitch;
    const double criticalDose = p.aces.criticalDose * beam.efficiency;
    const plan::AcesParameters& acesParameters = p.aces;
    InverseResult result;
    result.plan.machine.layerThickness = p.aces.layerThickness;
    result.plan.machine.laserPower = p.aces.laserPower;
    result.plan.machine.beamRadius = beam.radius;
    result.plan.layers.resize(regions.size());
    result.layers.resize(regions.size());
    result.compensation.resize(regions.size());
    std::vector<SurfaceGrid> deposits(regions.size(), grid.surface());
    for (int k = int(regions.size()) - 1; k >= 0; --k) {
        plan::LayerPlan& layer = result.plan.layers[k];
        layer.z = tops[k];
        const geometry::PolygonSet& region = regions[k];
        if (region.empty()) continue;
        SurfaceGrid transmitted = grid.surface();
        if (p.compensate)
            transmitted = transmittedExposure(*model, deposits, k, beam.attenuationLength);
        plan::AcesDesign design = plan::designAces(acesParameters, region);
        const double etar = design.targetDose * beam.efficiency;
        result.targetDose = etar;
        plan::LayerPlan aces = plan::planAcesLayer(region, design, p.aces.laserPower, tops[k]);

        LayerProblem problem;
        problem.model = model;
        problem.cellArea = cellArea;
        problem.counted = insideMask(region.offset(reff), transmitted);
        const std::vector<char> inside = insideMask(
            p.wallOnContour ? region.offset(targetWallShift(acesParameters, design.targetDose))
                            : region,
            transmitted);
        const std::vector<char> allowed = insideMask(region.offset(0.5 * ip.dotPitch), transmitted);
        problem.offset.assign(inside.size(), 0.0f);
        LayerCompensation& rec = result.compensation[k];
        for (size_t c = 0; c < inside.size(); ++c) {
            double target = inside[c] ? etar : 0.0, excess = transmitted.values[c] - target;
            problem.offset[c] = float(excess);
            if (excess > 0.05 * etar) rec.uncompensableArea += cellArea;
            rec.uncompensableMax = std::max(rec.uncompensableMax, excess / etar);
            if (!inside[c] && transmitted.values[c] >= criticalDose)
                rec.curingOutsideArea += cellArea;
            rec.compensated |= inside[c] && transmitted.values[c] > 0.01 * etar;
        }
        // Dots on every stride-th cell centre, and the ACES deposit gathered onto the nearest.
        std::vector<long> dotOf(inside.size(), -1);
        for (int j = stride / 2; j < grid.ny; j += stride)
            for (int i = stride / 2; i < grid.nx; i += stride) {
                size_t c = size_t(j) * grid.nx + i;
                if (!allowed[c]) continue;
                dotOf[c] = long(problem.dots.size());
                problem.dots.push_back(c);
            }
        SurfaceGrid acesDeposit = grid.surface();
        exposure::depositLayer(aces, acesDeposit);
        std::vector<double> x(problem.dots.size(), 0.0);
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i) {
                float v = acesDeposit.values[size_t(j) * grid.nx + i];
                if (v == 0) continue;
                int di = std::min(i / stride * stride + stride / 2, grid.nx - 1);
                int dj = std::min(j / stride * stride + stride / 2, grid.ny - 1);
                long d = dotOf[size_t(dj) * grid.nx + di];
                if (d >= 0) x[d] += v * cellArea;
            }
        InverseLayerReport& rep = result.layers[k];
        rep.dots = int(problem.dots.size());
        rep.acesObjective = problem.value(model->layerMap(acesDeposit, 0.0));
        rep.startObjective = problem.value(problem.forward(x));
        double best = 0;
        std::vector<double> solution = solve(problem, x, ip.iterations, best, rep.iterations);
        if (!(best < rep.acesObjective)) {
            layer = aces;
            rep.keptAces = true;
            rep.finalObjective = rep.acesObjective;
        } else {
            rep.finalObjective = best;
            for (size_t d = 0; d < solution.size(); ++d)
                if (solution[d] > 0)
                    layer.points.push_back(
                        {grid.originX + (problem.dots[d] % grid.nx + 0.5) * grid.pitch,
                         grid.originY + (problem.dots[d] / grid.nx + 0.5) * grid.pitch,
                         solution[d]});
        }
        exposure::depositLayer(layer, deposits[k]);
    }
    return result;
}

}  // namespace vpsim::optimise
