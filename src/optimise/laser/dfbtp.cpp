#include "vpsim/optimise/laser/dfbtp.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/progress.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/optimise/solvers/qp_active_set.h"
#include "vpsim/plan/feature_blocks.h"

namespace vpsim::optimise {
namespace {

using exposure::SurfaceGrid;

/// What one layer's feature QPs need.
struct LayerContext {
    const DfbtpParameters* p = nullptr;
    double w = 0, efficiency = 1, etar = 0, roff = 0, reff = 0;
    const geometry::PolygonSet* region = nullptr;
    std::vector<char> inside, middle;  ///< cell masks: region, middle area
    SurfaceGrid goal, planned;         ///< target after compensation; exposure planned so far
};

double bilinear(const SurfaceGrid& g, double x, double y) {
    double fx = (x - g.originX) / g.pitch - 0.5, fy = (y - g.originY) / g.pitch - 0.5;
    int i = int(std::floor(fx)), j = int(std::floor(fy));
    double tx = fx - i, ty = fy - j, sum = 0;
    for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di) {
            int ii = std::clamp(i + di, 0, g.nx - 1), jj = std::clamp(j + dj, 0, g.ny - 1);
            sum += (di ? tx : 1 - tx) * (dj ? ty : 1 - ty) * g.at(ii, jj);
        }
    return sum;
}

double missingAt(const LayerContext& c, double x, double y) {
    return std::max(bilinear(c.goal, x, y) - bilinear(c.planned, x, y), 0.0);
}

SurfaceGrid depositOf(const exposure::ExposureModel& model, const plan::LayerPlan& layer) {
    SurfaceGrid deposit = model.grid().surface();
    exposure::depositLayer(layer, deposit);
    return deposit;
}

SurfaceGrid mapOf(exposure::ExposureModel& model, const plan::LayerPlan& layer) {
    return model.layerMap(depositOf(model, layer), 0.0);
}

/// Seed Eq. 17: one linear edge as rows of constant line density lambda_j (mJ/mm) at distances
/// u_j across the edge; a row's exposure at distance u is eff sqrt(2/pi)/W exp(-2 (u-u_j)^2/W^2)
/// lambda_j (Eq. C.6). The missing exposure is averaged over five stations along the block.
/// One edge block's rows, in offset order: the row vectors (speed 0 where a row gets no energy)
/// and the pieces that continue a row through the corner block at its start (`before`, in scan
/// order) and at its end (`after`), on the same line, so that the scanner runs them with the
/// row as one power-modulated line instead of jumping to a corner dot row.
struct EdgeRows {
    std::vector<double> offsets;  ///< u_j, mm along the inward normal
    std::vector<plan::LaserVector> rows;
    std::vector<std::vector<plan::LaserVector>> before, after;
};

EdgeRows planEdge(const plan::EdgeBlock& e, const LayerContext& c) {
    const DfbtpParameters& p = *c.p;
    std::vector<double> us, ecs, lifts, rows;
    for (double u = -c.reff; u <= c.roff + c.reff + 1e-12; u += p.gridPitch) {
        double sum = 0;
        for (int k = 0; k < 5; ++k) {
            double s = e.start + (k + 0.5) / 5 * (e.end - e.start);
            glm::dvec2 q = e.a + s * e.tangent + u * e.normal;
            sum += missingAt(c, q.x, q.y);
        }
        us.push_back(u);
        ecs.push_back(sum / 5);
        lifts.push_back(u < 0 ? p.liftOutside : u < c.roff ? p.liftEdge : p.liftInside);
    }
    for (double u = -c.reff; u <= c.roff + 1e-12; u += p.dotPitch) rows.push_back(u);
    const int m = int(us.size()), n = int(rows.size());
    Eigen::MatrixXd K(m, n);
    Eigen::VectorXd b(m), d(m);
    const double amp = c.efficiency * std::sqrt(2.0 / M_PI) / c.w;
    for (int i = 0; i < m; ++i) {
        b(i) = ecs[i];
        d(i) = ecs[i] + lifts[i] * c.etar;
        for (int j = 0; j < n; ++j) {
            double du = (us[i] - rows[j]) / c.w;
            K(i, j) = amp * std::exp(-2 * du * du);
        }
    }
    LsqQpResult qp = solveLsqQp(K, b, K, d, 1e-12 * K.squaredNorm() / n);
    const double power = p.aces.laserPower;
    EdgeRows out;
    out.offsets = rows;
    out.before.resize(size_t(n));
    out.after.resize(size_t(n));
    for (int j = 0; j < n; ++j) {
        const double lambda = qp.x(j);
        const glm::dvec2 a = e.a + e.start * e.tangent + rows[j] * e.normal,
                         z = e.a + e.end * e.tangent + rows[j] * e.normal;
        out.rows.push_back(
            {a.x, a.y, z.x, z.y, power, lambda > 1e-9 * c.etar * c.w ? power / lambda : 0.0});
    }
    return out;
}

/// A corner's candidate dot: where it lies and, on a row line, the piece of that line it runs
/// as (its edge, row and place in the continuation).
struct CornerDot {
    glm::dvec2 at;
    int edge = -1, row = 0;  ///< edge -1: a grid dot (no edge row to continue)
    bool after = false;      ///< continues the row past the edge block's end
    glm::dvec2 from, to;     ///< the piece of the row line
};

/// The corner's candidates on the lines of the rows of the edges that meet at it, one piece a
/// dot pitch long after another from the edge block's end (incoming edge) or back from its
/// start (outgoing), to the far side of the corner block.
std::vector<CornerDot> rowLineDots(const plan::CornerBlock& corner,
                                   const std::vector<plan::EdgeBlock>& edges,
                                   const std::vector<EdgeRows>& rows, int incoming, int outgoing,
                                   double pitch) {
    std::vector<CornerDot> dots;
    for (int side = 0; side < 2; ++side) {
        const int k = side == 0 ? incoming : outgoing;
        const plan::EdgeBlock& e = edges[size_t(k)];
        const double length = glm::length(e.b - e.a);
        const int pieces = int(std::floor((2 * corner.halfSize + 1e-9) / pitch));
        for (size_t j = 0; j < rows[size_t(k)].offsets.size(); ++j)
            for (int i = 0; i < pieces; ++i) {
                const double s0 = side == 0 ? e.end + i * pitch : e.start - (i + 1) * pitch;
                const double s1 = s0 + pitch;
                if (s0 < -corner.halfSize - 1e-9 || s1 > length + corner.halfSize + 1e-9) continue;
                const glm::dvec2 n = rows[size_t(k)].offsets[j] * e.normal;
                CornerDot d;
                d.edge = k, d.row = int(j), d.after = side == 0;
                d.from = e.a + s0 * e.tangent + n, d.to = e.a + s1 * e.tangent + n;
                d.at = 0.5 * (d.from + d.to);
                dots.push_back(d);
            }
    }
    return dots;
}

/// The corner's candidates on a grid of the dot pitch around its vertex.
std::vector<CornerDot> gridDots(const plan::CornerBlock& corner, double pitch) {
    std::vector<CornerDot> dots;
    const int reach = int(std::floor(corner.halfSize / pitch));
    for (int j = -reach; j <= reach; ++j)
        for (int i = -reach; i <= reach; ++i) {
            CornerDot d;
            d.at = corner.vertex + pitch * glm::dvec2(i, j);
            dots.push_back(d);
        }
    return dots;
}

/// Seed Eq. 19: one corner as dots of energy T_k around the vertex; a dot's exposure is
/// eff 2/(pi W^2) exp(-2 r^2/W^2) T_k. Evaluated on the grid cells of the block grown by Reff.
/// Dots on a row line become pieces of that row (`rows`), grid dots layer points.
int planCorner(const plan::CornerBlock& corner, const std::vector<CornerDot>& candidates,
               LayerContext& c, std::vector<EdgeRows>& rows, plan::LayerPlan& out) {
    const DfbtpParameters& p = *c.p;
    const SurfaceGrid& g = c.planned;
    const geometry::PolygonSet grown = c.region->offset(0.5 * c.w);
    std::vector<CornerDot> dots;
    for (const CornerDot& d : candidates) {
        const glm::dvec2 q = d.at;
        if (!grown.contains(q)) continue;
        double need = 0;  // worth a variable only where something is missing nearby
        for (glm::dvec2 o : {glm::dvec2(0), glm::dvec2(0.5 * c.w, 0), glm::dvec2(-0.5 * c.w, 0),
                             glm::dvec2(0, 0.5 * c.w), glm::dvec2(0, -0.5 * c.w)})
            need = std::max(need, missingAt(c, q.x + o.x, q.y + o.y));
        if (need > 0.01 * c.etar) dots.push_back(d);
    }
    if (dots.empty()) return 0;
    const double extent = corner.halfSize + c.reff;
    std::vector<size_t> cells;
    for (int j = 0; j < g.ny; ++j) {
        if (std::abs(g.centreY(j) - corner.vertex.y) > extent) continue;
        for (int i = 0; i < g.nx; ++i)
            if (std::abs(g.centreX(i) - corner.vertex.x) <= extent)
                cells.push_back(size_t(j) * g.nx + i);
    }
    const int m = int(cells.size()), n = int(dots.size());
    Eigen::MatrixXd K(m, n);
    Eigen::VectorXd b(m), d(m);
    const double amp = c.efficiency * 2.0 / (M_PI * c.w * c.w);
    for (int r = 0; r < m; ++r) {
        size_t cell = cells[r];
        double x = g.centreX(int(cell % g.nx)), y = g.centreY(int(cell / g.nx));
        double missing = std::max(double(c.goal.values[cell]) - c.planned.values[cell], 0.0);
        double lift = !c.inside[cell] ? p.liftOutside : c.middle[cell] ? p.liftInside : p.liftEdge;
        b(r) = missing;
        d(r) = missing + lift * c.etar;
        for (int k = 0; k < n; ++k) {
            double dx = (x - dots[k].at.x) / c.w, dy = (y - dots[k].at.y) / c.w;
            K(r, k) = amp * std::exp(-2 * (dx * dx + dy * dy));
        }
    }
    LsqQpResult qp = solveLsqQp(K, b, K, d, 1e-12 * K.squaredNorm() / n);
    Eigen::VectorXd added = K * qp.x;
    for (int r = 0; r < m; ++r) c.planned.values[cells[r]] += float(added(r));
    int placed = 0;
    const double power = p.aces.laserPower;
    for (int k = 0; k < n; ++k) {
        if (!(qp.x(k) > 0)) continue;
        ++placed;
        const CornerDot& dot = dots[k];
        if (dot.edge < 0) {
            out.points.push_back({dot.at.x, dot.at.y, qp.x(k)});
            continue;
        }
        const double lambda = qp.x(k) / glm::length(dot.to - dot.from);  // mJ/mm along the piece
        EdgeRows& r = rows[size_t(dot.edge)];
        (dot.after ? r.after : r.before)[size_t(dot.row)].push_back(
            {dot.from.x, dot.from.y, dot.to.x, dot.to.y, power, power / lambda});
    }
    return placed;
}

/// The edge rows in scan order: around each contour (its edge blocks in contour order), one
/// offset after the other, as ACES's border loops run, each row with the pieces that continue it
/// through its corner blocks (one line at constant speed, power modulated along it). Serpentine
/// rows along one edge reversed at every row instead.
std::vector<plan::LaserVector> edgeLoops(const std::vector<plan::EdgeBlock>& edges,
                                         std::vector<EdgeRows>& rows) {
    std::vector<plan::LaserVector> out;
    auto add = [&](const plan::LaserVector& v) {
        if (v.speed > 0) out.push_back(v);
    };
    for (size_t first = 0; first < edges.size();) {
        size_t last = first;  // edges of one contour follow each other, end to start
        while (last + 1 < edges.size() && glm::length(edges[last].b - edges[last + 1].a) <= 1e-9)
            ++last;
        size_t offsets = 0;
        for (size_t e = first; e <= last; ++e) offsets = std::max(offsets, rows[e].rows.size());
        for (size_t j = 0; j < offsets; ++j)
            for (size_t e = first; e <= last; ++e) {
                if (j >= rows[e].rows.size()) continue;
                std::vector<plan::LaserVector>& before = rows[e].before[j];
                std::reverse(before.begin(), before.end());  // planned outwards from the row
                for (const auto& v : before) add(v);
                add(rows[e].rows[j]);
                for (const auto& v : rows[e].after[j]) add(v);
            }
        first = last + 1;
    }
    return out;
}

/// The edge blocks ending (`incoming`) and starting (`outgoing`) at a corner's vertex, -1 where
/// the edge there has no block.
void edgesAt(const plan::CornerBlock& corner, const std::vector<plan::EdgeBlock>& edges,
             int& incoming, int& outgoing) {
    incoming = outgoing = -1;
    for (size_t e = 0; e < edges.size(); ++e) {
        if (glm::length(edges[e].b - corner.vertex) <= 1e-9) incoming = int(e);
        if (glm::length(edges[e].a - corner.vertex) <= 1e-9) outgoing = int(e);
    }
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
