#include "vpsim/planners/inverse_planner.h"

#include <algorithm>
#include <cmath>

#include "vpsim/optimise/laser/inverse.h"
#include "vpsim/planners/laser_layers.h"
#include "vpsim/planners/laser_plan_options.h"
#include "vpsim/planners/plan_size.h"

namespace vpsim::planners {

KeyTable inverseKeyTable() {
    KeyTable table = laserPlanKeyTable(plan::AcesEdge::CureAtContour);
    table.add(laserOptimiserKeyTable("dot grid pitch, a whole number of grid cells"));
    table.add({{
        integerKey("iterations", 30, "projected-gradient iterations per layer").in(0, 100000),
        integerKey("coarse_iterations", 40, "iterations first on a grid at the dot pitch (0: none)")
            .in(0, 100000),
    }});
    return table;
}

optimise::InverseParameters readInverseParameters(const KeyReader& keys) {
    optimise::InverseParameters p;
    p.dotPitch = keys.quantity("dot_pitch");
    p.base.gridPitch = keys.quantity("grid_pitch");
    p.base.compensate = keys.boolean("compensate");
    p.iterations = int(keys.integer("iterations"));
    p.coarseIterations = int(keys.integer("coarse_iterations"));
    return p;
}

namespace {

class InversePlanner : public Planner {
public:
    explicit InversePlanner(const KeyReader& keys)
        : mOptions(readLaserPlanOptions(keys)), mP(readInverseParameters(keys)) {}
    plan::Process process() const override { return plan::Process::Laser; }
    plan::OrderMethod partOrder() const override { return mOptions.order; }

    plan::ScanPlan plan(const PlannerInputs& in) override {
        optimise::InverseParameters p = mP;
        p.base.aces = acesParameters(mOptions, in.beam, in.machine, in.criticalDose);
        p.base.wallOnContour = mOptions.aces.edge == plan::AcesEdge::CureAtContour;
        checkLaserDose(p.base.aces, in.machine);
        plan::ScanPlan empty = plan::emptyPlan(in.layers, in.machine);
        optimise::InverseResult r =
            optimise::planInverse(layerRegions(in), layerTops(empty), p, in.beam);
        r.plan.machine = empty.machine;
        double aces = 0, final = 0;
        int kept = 0;
        for (const auto& l : r.layers)
            aces += l.acesObjective, final += l.finalObjective, kept += l.keptAces;
        mSummary = {{"inverse",
                     {{"target_dose_mJ_per_cm2", r.targetDose * 100},
                      {"objective_aces_mJ2_per_mm4", aces},
                      {"objective_final_mJ2_per_mm4", final},
                      {"layers_kept_aces", kept},
                      {"iterations", p.iterations},
                      {"dot_pitch_um", p.dotPitch * 1e3},
                      {"compensation", p.base.compensate},
                      {"transmitted", compensationJson(r.compensation)}}}};
        // The dots lie on every stride-th cell of the planning grid (optimise/laser/inverse.h).
        const double dotSpacing =
            double(std::max(1L, std::lround(p.dotPitch / p.base.gridPitch))) * p.base.gridPitch;
        mSummary.update(fitLaserPlan(r.plan, p.base.aces, in.machine, dotSpacing));
        return r.plan;
    }
    nlohmann::json summary() const override { return mSummary; }

    PlanSize estimateSize(const PlanSizeInputs& inputs) const override {
        return laserOptimiserPlanSize(inputs, mP.base.gridPitch, mP.dotPitch,
                                      mP.iterations + mP.coarseIterations / 8.0, true);
    }

private:
    LaserPlanOptions mOptions;
    optimise::InverseParameters mP;
    nlohmann::json mSummary = nlohmann::json::object();
};

}  // namespace

void registerInversePlanner(PlannerRegistry& registry) {
    registry.add({"inverse",
                  "whole-layer bounded least squares of dot energies through the exposure "
                  "model's forward and adjoint, warm-started from ACES, top-down compensation",
                  inverseKeyTable(),
                  [](const KeyReader& keys) { return std::make_unique<InversePlanner>(keys); }});
}

}  // namespace vpsim::planners
