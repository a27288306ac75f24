#include "vpsim/planners/dfbtp_planner.h"

#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/planners/laser_layers.h"
#include "vpsim/planners/laser_plan_options.h"
#include "vpsim/planners/plan_size.h"

namespace vpsim::planners {

KeyTable dfbtpKeyTable() {
    KeyTable table = laserPlanKeyTable();
    table.add(laserOptimiserKeyTable("corner dot grid and edge row spacing"));
    table.add({{
        numberKey("lift_outside", 0.15, "a_i outside the part, fraction of Etar").in(0, 10),
        numberKey("lift_edge", 0.25, "a_i in the under-exposed band inside the contour").in(0, 10),
        numberKey("lift_inside", 0.05, "a_i inside the middle area").in(0, 10),
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
        : mOptions(readLaserPlanOptions(keys)), mP(readDfbtpParameters(keys)) {}
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
        return r.plan;
    }
    nlohmann::json summary() const override { return mSummary; }

    PlanSize estimateSize(const PlanSizeInputs& inputs) const override {
        return laserOptimiserPlanSize(inputs, mP.gridPitch, mP.dotPitch, 4, false);
    }

private:
    LaserPlanOptions mOptions;
    optimise::DfbtpParameters mP;
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
