#include "vpsim/optimise/dfbtp_strategy.h"

#include "vpsim/optimise/dfbtp_config.h"
#include "vpsim/plan/feature_blocks.h"
#include "vpsim/plan/laser_plan_options.h"

namespace vpsim::optimise {
namespace {

std::vector<geometry::PolygonSet> regionsOf(const plan::PlannerInputs& in) {
    std::vector<geometry::PolygonSet> regions;
    for (const auto& layer : in.layers.layers) regions.push_back(layer.region);
    return regions;
}

std::vector<double> topsOf(const plan::ScanPlan& empty) {
    std::vector<double> tops;
    for (const auto& layer : empty.layers) tops.push_back(layer.z);
    return tops;
}

nlohmann::json compensationJson(const std::vector<LayerCompensation>& layers) {
    double area = 0, worst = 0, curing = 0;
    nlohmann::json where = nlohmann::json::array();
    for (size_t k = 0; k < layers.size(); ++k) {
        area += layers[k].uncompensableArea;
        curing += layers[k].curingOutsideArea;
        worst = std::max(worst, layers[k].uncompensableMax);
        if (layers[k].uncompensableArea > 0)
            where.push_back({{"layer", k},
                             {"area_mm2", layers[k].uncompensableArea},
                             {"max_excess_over_Etar", layers[k].uncompensableMax}});
    }
    return {{"uncompensable_area_mm2", area},
            {"uncompensable_max_excess_over_Etar", worst},
            {"transmitted_cures_outside_area_mm2", curing},
            {"uncompensable_layers", where}};
}

class DfbtpPlanner : public plan::Planner {
public:
    DfbtpPlanner(plan::LaserPlanOptions options, DfbtpParameters p) : mOptions(options), mP(p) {}
    plan::Process process() const override { return plan::Process::Laser; }
    plan::ScanPlan plan(const plan::PlannerInputs& in) override {
        DfbtpParameters p = mP;
        p.aces = plan::acesParameters(mOptions, in.beam, in.machine, in.criticalDose);
        p.wallOnContour = mOptions.aces.edge == plan::AcesEdge::CureAtContour;
        plan::ScanPlan empty = plan::emptyPlan(in.layers, in.machine);
        DfbtpResult r = planDfbtp(regionsOf(in), topsOf(empty), p, in.beam);
        r.plan.machine = empty.machine;
        int edges = 0, corners = 0, dots = 0;
        for (const auto& l : r.layers)
            edges += l.edgeBlocks, corners += l.cornerBlocks, dots += l.cornerDots;
        mSummary = {
            {"dfbtp",
             {{"target_dose_mJ_per_cm2", r.targetDose * 100},
              {"edge_blocks", edges},
              {"corner_blocks", corners},
              {"corner_dots", dots},
              {"compensation", p.compensate},
              {"target_wall_shift_um",
               p.wallOnContour ? targetWallShift(p.aces, r.targetDose / in.beam.efficiency) * 1e3
                               : 0.0},
              {"lifts", {mP.liftOutside, mP.liftEdge, mP.liftInside}},
              {"transmitted", compensationJson(r.layers)}}}};
        return r.plan;
    }
    nlohmann::json summary() const override { return mSummary; }

private:
    plan::LaserPlanOptions mOptions;
    DfbtpParameters mP;
    nlohmann::json mSummary = nlohmann::json::object();
};

class InversePlanner : public plan::Planner {
public:
    InversePlanner(plan::LaserPlanOptions options, InverseParameters p)
        : mOptions(options), mP(p) {}
    plan::Process process() const override { return plan::Process::Laser; }
    plan::ScanPlan plan(const plan::PlannerInputs& in) override {
        InverseParameters p = mP;
        p.base.aces = plan::acesParameters(mOptions, in.beam, in.machine, in.criticalDose);
        p.base.wallOnContour = mOptions.aces.edge == plan::AcesEdge::CureAtContour;
        plan::ScanPlan empty = plan::emptyPlan(in.layers, in.machine);
        InverseResult r = planInverse(regionsOf(in), topsOf(empty), p, in.beam);
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
        return r.plan;
    }
    nlohmann::json summary() const override { return mSummary; }

private:
    plan::LaserPlanOptions mOptions;
    InverseParameters mP;
    nlohmann::json mSummary = nlohmann::json::object();
};

}  // namespace

void registerLaserOptimisers(plan::PlannerRegistry& registry) {
    std::vector<ConfigKeyDoc> dfbtpKeys = plan::laserPlanKeys();
    for (auto k : dfbtpKeyDocs()) dfbtpKeys.push_back(k);
    registry.add({"dfbtp",
                  "disassembled-feature-based planning (seed 000 Section III): ACES middle area, "
                  "edge and corner least squares, top-down compensation of print-through",
                  dfbtpKeys, [](const ConfigNode& section) {
                      auto options = plan::readLaserPlanOptions(section);
                      return std::make_unique<DfbtpPlanner>(options, readDfbtpKeys(section));
                  }});
    std::vector<ConfigKeyDoc> inverseKeys = plan::laserPlanKeys();
    for (auto k : inverseKeyDocs()) inverseKeys.push_back(k);
    registry.add({"inverse",
                  "whole-layer bounded least squares of dot energies through the exposure "
                  "model's forward and adjoint, warm-started from ACES, top-down compensation",
                  inverseKeys, [](const ConfigNode& section) {
                      auto options = plan::readLaserPlanOptions(section);
                      if (!section.has("edge")) options.aces.edge = plan::AcesEdge::CureAtContour;
                      return std::make_unique<InversePlanner>(options, readInverseKeys(section));
                  }});
}

}  // namespace vpsim::optimise
