#include "vpsim/planners/dfbtp_planner.h"

#include "vpsim/core/log.h"
#include "vpsim/core/text.h"
#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/optimise/laser/inverse_shape.h"
#include "vpsim/planners/laser_layers.h"
#include "vpsim/planners/laser_plan_options.h"
#include "vpsim/planners/plan_size.h"

namespace vpsim::planners {

KeyTable dfbtpKeyTable() {
    KeyTable table = laserPlanKeyTable();
    table.add(laserOptimiserKeyTable(
        "corner dot grid and edge row spacing (each row a scan line: it sets the build time)",
        "40 um"));
    table.add({{
        numberKey("lift_outside", 0.15, "a_i outside the part, fraction of Etar").in(0, 10),
        numberKey("lift_edge", 0.25, "a_i in the under-exposed band inside the contour").in(0, 10),
        numberKey("lift_inside", 0.05, "a_i inside the middle area").in(0, 10),
        choiceKey("edges", {"qp", "shape"}, "qp",
                  "qp: edges and corners by the seed's least squares on each layer's exposure; "
                  "shape: then the dots within edge_band of the contour re-optimised on what "
                  "cures in 3D (inverse's shape objective), the middle area held"),
        quantityKey("edge_band", dim::LENGTH, "100 um", "edges: shape: width inside the contour")
            .in(1e-3, 10),
    }});
    return table;
}

optimise::DfbtpParameters readDfbtpParameters(const KeyReader& keys) {
    optimise::DfbtpParameters p;
    p.dotPitch = keys.quantity("dot_pitch");
    p.gridPitch = keys.quantity("grid_pitch");
    p.compensate = keys.boolean("compensate");
    p.liftOutside = keys.number("lift_outside");
    p.liftEdge = keys.number("lift_edge");
    p.liftInside = keys.number("lift_inside");
    return p;
}

namespace {

class DfbtpPlanner : public Planner {
public:
    explicit DfbtpPlanner(const KeyReader& keys)
        : mOptions(readLaserPlanOptions(keys)),
          mP(readDfbtpParameters(keys)),
          mShapeEdges(keys.choice("edges") == "shape") {
        mShape.edgeBand = keys.quantity("edge_band");
    }
    plan::Process process() const override { return plan::Process::Laser; }
    plan::OrderMethod partOrder() const override { return mOptions.order; }

    plan::ScanPlan plan(const PlannerInputs& in) override {
        optimise::DfbtpParameters p = mP;
        p.aces = acesParameters(mOptions, in.beam, in.machine, in.criticalDose);
        p.wallOnContour = mOptions.aces.edge == plan::AcesEdge::CureAtContour;
        checkLaserDose(p.aces, in.machine);
        plan::ScanPlan empty = plan::emptyPlan(in.layers, in.machine);
        optimise::DfbtpResult r =
            optimise::planDfbtp(layerRegions(in), layerTops(empty), p, in.beam);
        r.plan.machine = empty.machine;
        int edges = 0, corners = 0, dots = 0;
        for (const auto& l : r.layers)
            edges += l.edgeBlocks, corners += l.cornerBlocks, dots += l.cornerDots;
        const double shift =
            p.wallOnContour
                ? optimise::targetWallShift(p.aces, r.targetDose / in.beam.efficiency) * 1e3
                : 0.0;
        mSummary = {{"dfbtp",
                     {{"target_dose_mJ_per_cm2", r.targetDose * 100},
                      {"edge_blocks", edges},
                      {"corner_blocks", corners},
                      {"corner_dots", dots},
                      {"compensation", p.compensate},
                      {"target_wall_shift_um", shift},
                      {"lifts", {mP.liftOutside, mP.liftEdge, mP.liftInside}},
                      {"transmitted", compensationJson(r.layers)}}}};
        mSummary.update(fitLaserPlan(r.plan, p.aces, in.machine, p.dotPitch));
        if (mShapeEdges) return shapeEdges(in, std::move(r.plan), p);
        return r.plan;
    }
    nlohmann::json summary() const override { return mSummary; }

    PlanSize estimateSize(const PlanSizeInputs& inputs) const override {
        if (mShapeEdges) return shapePlanSize(inputs, mP.gridPitch, mP.dotPitch, mShape);
        return laserOptimiserPlanSize(inputs, mP.gridPitch, mP.dotPitch, 4, false);
    }

private:
    /// `edges: shape`: the dots within the edge band re-optimised on the shape objective from
    /// the DFBTP plan as the machine runs it, the marks deeper inside held; the DFBTP plan is
    /// returned where that does not lower J (optimise::planInverseShape).
    plan::ScanPlan shapeEdges(const PlannerInputs& in, plan::ScanPlan start,
                              const optimise::DfbtpParameters& p) {
        const auto slices = shapeSlices(in, start, mShape.slicesPerLayer);
        nlohmann::json fit;
        auto toMachine = [&](plan::ScanPlan& dots) {
            fit = fitLaserPlan(dots, p.aces, in.machine, p.dotPitch);
        };
        optimise::ShapeResult r = optimise::planInverseShape(
            layerRegions(in), slices, start, p.gridPitch, p.dotPitch, mShape, in.beam,
            in.machine.layerThickness, in.criticalDose, toMachine);
        logInfo("dfbtp (shape edges): J " + formatNumber(r.objectiveStart, 6) + " -> " +
                formatNumber(r.objectiveFinal, 6) + " mm^3" +
                (r.keptStart ? " (no improvement: the DFBTP plan returned)" : ""));
        mSummary["dfbtp"]["shape_edges"] = {{"edge_band_um", mShape.edgeBand * 1e3},
                                            {"objective_start_mm3", r.objectiveStart},
                                            {"objective_final_mm3", r.objectiveFinal},
                                            {"kept_start", r.keptStart},
                                            {"dots", r.dots},
                                            {"iterations", r.iterations}};
        if (!r.keptStart) mSummary.update(fit);
        return r.plan;
    }

    LaserPlanOptions mOptions;
    optimise::DfbtpParameters mP;
    bool mShapeEdges = false;
    optimise::ShapeParameters mShape;
    nlohmann::json mSummary = nlohmann::json::object();
};

}  // namespace

void registerDfbtpPlanner(PlannerRegistry& registry) {
    registry.add({"dfbtp",
                  "disassembled-feature-based planning (seed 000 Section III): ACES middle area, "
                  "edge and corner least squares, top-down compensation of print-through",
                  dfbtpKeyTable(),
                  [](const KeyReader& keys) { return std::make_unique<DfbtpPlanner>(keys); }});
}

}  // namespace vpsim::planners
