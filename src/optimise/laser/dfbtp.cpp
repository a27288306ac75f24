#include "vpsim/optimise/laser/dfbtp.h"

#include "dfbtp_features.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/common.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/plan/feature_blocks.h"

namespace vpsim::optimise {
namespace {

using namespace dfbtp;

SurfaceGrid depositOf(const exposure::ExposureModel& model, const plan::LayerPlan& layer) {
    SurfaceGrid deposit = model.grid().surface();
    exposure::depositLayer(layer, deposit);
    return deposit;
}

SurfaceGrid mapOf(exposure::ExposureModel& model, const plan::LayerPlan& layer) {
    return model.layerMap(depositOf(model, layer), 0.0);
}

/// Eq. 22 for the middle area: the ACES vectors cut into pieces of about two grid cells, each at
/// the speed that gives the local compensated target (the plan's speed scaled by Etar / goal);
/// pieces where nothing is left to expose are dropped.
std::vector<plan::LaserVector> modulatedHatch(const std::vector<plan::LaserVector>& vectors,
                                              const LayerContext& c) {
    std::vector<plan::LaserVector> out;
    const double piece = 2 * c.p->gridPitch;
    for (const auto& v : vectors) {
        double length = std::hypot(v.x1 - v.x0, v.y1 - v.y0);
        int pieces = std::max(1, int(std::ceil(length / piece)));
        for (int k = 0; k < pieces; ++k) {
            double t0 = double(k) / pieces, t1 = double(k + 1) / pieces, tm = 0.5 * (t0 + t1);
            double goal = bilinear(c.goal, v.x0 + tm * (v.x1 - v.x0), v.y0 + tm * (v.y1 - v.y0));
            if (!(goal > 0.01 * c.etar)) continue;
            out.push_back({v.x0 + t0 * (v.x1 - v.x0), v.y0 + t0 * (v.y1 - v.y0),
                           v.x0 + t1 * (v.x1 - v.x0), v.y0 + t1 * (v.y1 - v.y0), v.power,
                           v.speed * std::max(1.0, c.etar / goal)});
        }
    }
    return out;
}

}  // namespace

double targetWallShift(const plan::AcesParameters& a, double targetDose) {
    const double rh =
        0.05;  // a dense field: the continuous sheet's edge is rh/2 beyond its last line
    double y =
        plan::acesContourDistance(rh, a.criticalDose / targetDose,
                                  (a.layerThickness - a.depthOfMaximum) / a.attenuationLength, 1.0);
    return (0.5 * rh - y) * a.beamRadius;
}

exposure::ExposureGrid planningGrid(const std::vector<geometry::PolygonSet>& regions,
                                    double beamRadius, double pitch) {
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const auto& r : regions) {
        if (r.empty()) continue;
        auto [a, b] = r.bounds();
        lo = glm::min(lo, a);
        hi = glm::max(hi, b);
    }
    if (lo.x > hi.x) throw InputError("DFBTP: every layer region is empty");
    double margin = plan::effectiveRadius(beamRadius) + 2 * beamRadius;
    return exposure::ExposureGrid::covering(lo.x, lo.y, hi.x, hi.y, margin, pitch, 1);
}

exposure::SurfaceGrid transmittedExposure(exposure::ExposureModel& model,
                                          const std::vector<exposure::SurfaceGrid>& deposits, int k,
                                          double attenuationLength) {
    SurfaceGrid sum = model.grid().surface();
    const double lt = model.layerThickness();
    for (int j = k + 1; j < int(deposits.size()); ++j) {
        double depth = (j - k) * lt;
        if (std::exp(-depth / attenuationLength) < 1e-4) break;
        SurfaceGrid part = model.layerMap(deposits[j], depth);
        for (size_t c = 0; c < sum.values.size(); ++c) sum.values[c] += part.values[c];
    }
    return sum;
}

namespace {

/// The goal Etar - E_t clipped at 0 (Eq. 22; E_t = 0 without compensation) on c.goal, and where
/// the transmitted exposure cannot be compensated (reports).
void setGoal(LayerContext& c, const SurfaceGrid& transmitted, double criticalDose,
             LayerCompensation& rec) {
    const double cellArea = transmitted.pitch * transmitted.pitch;
    c.goal = transmitted;
    for (size_t cell = 0; cell < c.goal.values.size(); ++cell) {
        double target = c.inside[cell] ? c.etar : 0.0;
        double sent = c.p->compensate ? transmitted.values[cell] : 0.0;
        double excess = sent - target;
        if (excess > 0.05 * c.etar) rec.uncompensableArea += cellArea;
        rec.uncompensableMax = std::max(rec.uncompensableMax, excess / c.etar);
        if (!c.inside[cell] && transmitted.values[cell] >= criticalDose)
            rec.curingOutsideArea += cellArea;
        c.goal.values[cell] = float(std::max(target - sent, 0.0));
        if (c.inside[cell] && sent > 0.01 * c.etar) rec.compensated = true;
    }
}

/// Edges (1D problems) then corners (2D), in increasing order of freedom, each on the exposure
/// of what is planned so far.
void planBlocks(exposure::ExposureModel& engine, const plan::FeatureBlocks& blocks, LayerContext& c,
                plan::LayerPlan& layer, LayerCompensation& rec) {
    c.planned = mapOf(engine, layer);
    std::vector<EdgeRows> rows;
    for (const auto& e : blocks.edges) rows.push_back(planEdge(e, c));
    rec.edgeBlocks = int(blocks.edges.size());
    plan::LayerPlan withEdges = layer;
    for (const auto& r : rows)
        for (const auto& v : r.rows)
            if (v.speed > 0) withEdges.vectors.push_back(v);
    if (withEdges.vectors.size() > layer.vectors.size()) c.planned = mapOf(engine, withEdges);
    for (const auto& corner : blocks.corners) {
        int incoming = 0, outgoing = 0;
        edgesAt(corner, blocks.edges, incoming, outgoing);
        const bool onRows = incoming >= 0 && outgoing >= 0 && incoming != outgoing;
        const std::vector<CornerDot> candidates =
            onRows ? rowLineDots(corner, blocks.edges, rows, incoming, outgoing, c.p->dotPitch)
                   : gridDots(corner, c.p->dotPitch);
        rec.cornerDots += planCorner(corner, candidates, c, rows, layer);
    }
    const std::vector<plan::LaserVector> edges = edgeLoops(blocks.edges, rows);
    layer.vectors.insert(layer.vectors.end(), edges.begin(), edges.end());
    rec.cornerBlocks = int(blocks.corners.size());
}

/// One layer: the ACES middle area (5% rule), its hatch modulated by the compensated goal, then
/// the edge and corner blocks. Returns the layer's Etar (mJ/mm^2 as the engine computes).
double planDfbtpLayer(exposure::ExposureModel& engine, const geometry::PolygonSet& region,
                      double top, const SurfaceGrid& transmitted, const DfbtpParameters& p,
                      const plan::AcesParameters& acesParameters, const kernel::FittedBeam& beam,
                      plan::LayerPlan& layer, LayerCompensation& rec) {
    plan::AcesDesign design = plan::designAces(acesParameters, region);
    LayerContext c;
    c.p = &p;
    c.w = beam.radius;
    c.efficiency = beam.efficiency;
    c.etar = design.targetDose * beam.efficiency;
    c.roff = design.edgeOffset;
    c.reff = plan::effectiveRadius(beam.radius);
    c.region = &region;
    plan::FeatureBlocks blocks = plan::disassembleFeatures(region, c.roff, c.reff, beam.radius);
    layer = plan::planAcesLayer(region, design, p.aces.laserPower, top);
    c.inside = insideMask(p.wallOnContour
                              ? region.offset(targetWallShift(acesParameters, design.targetDose))
                              : region,
                          transmitted);
    c.middle = insideMask(blocks.middle, transmitted);
    setGoal(c, transmitted, p.aces.criticalDose * beam.efficiency, rec);
    if (p.compensate && rec.compensated) layer.vectors = modulatedHatch(layer.vectors, c);
    planBlocks(engine, blocks, c, layer, rec);
    return c.etar;
}

}  // namespace

DfbtpResult planDfbtp(const std::vector<geometry::PolygonSet>& regions,
                      const std::vector<double>& tops, const DfbtpParameters& p,
                      const kernel::FittedBeam& beam, exposure::ExposureModel* model) {
    if (regions.size() != tops.size())
        throw InputError("DFBTP: one top height per layer region is needed");
    if (!(p.gridPitch > 0) || !(p.dotPitch > 0) || !(p.liftOutside >= 0) || !(p.liftEdge >= 0) ||
        !(p.liftInside >= 0))
        throw InputError("DFBTP: grid and dot pitch must be positive and the liftings >= 0");
    plan::AcesParameters acesParameters = p.aces;
    acesParameters.edge = plan::AcesEdge::SeedFivePercent;
    acesParameters.borderCount = 0;
    acesParameters.borderOffset.reset();
    std::unique_ptr<exposure::ExposureModel> own;
    if (!model) {
        own = std::make_unique<exposure::ExposureEngine>(
            planningGrid(regions, beam.radius, p.gridPitch), beam, p.aces.layerThickness);
        model = own.get();
    }
    exposure::ExposureModel& engine = *model;
    std::vector<SurfaceGrid> deposits(regions.size(), engine.grid().surface());
    DfbtpResult result;
    result.plan.machine.layerThickness = p.aces.layerThickness;
    result.plan.machine.laserPower = p.aces.laserPower;
    result.plan.machine.beamRadius = beam.radius;
    result.plan.layers.resize(regions.size());
    result.layers.resize(regions.size());
    Progress progress("DFBTP planner: layers", regions.size());
    for (int k = int(regions.size()) - 1; k >= 0;
         --k, progress.advance()) {  // top down (Eq. 21-22)
        plan::LayerPlan& layer = result.plan.layers[k];
        layer.z = tops[k];
        if (regions[k].empty()) continue;  // an empty layer deposits nothing
        const SurfaceGrid transmitted =
            transmittedExposure(engine, deposits, k, beam.attenuationLength);
        result.targetDose = planDfbtpLayer(engine, regions[k], tops[k], transmitted, p,
                                           acesParameters, beam, layer, result.layers[k]);
        deposits[k] = depositOf(engine, layer);
    }
    return result;
}

}  // namespace vpsim::optimise
