#include "vpsim/plan/aces_planner.h"

#include "vpsim/plan/laser_plan_options.h"

namespace vpsim::plan {
namespace {

class AcesPlanner : public Planner {
public:
    explicit AcesPlanner(LaserPlanOptions options) : mOptions(options) {}
    Process process() const override { return Process::Laser; }

    ScanPlan plan(const PlannerInputs& in) override {
        const AcesParameters aces = acesParameters(mOptions, in.beam, in.machine, in.criticalDose);
        ScanPlan plan = emptyPlan(in.layers, in.machine);
        mSummary = nlohmann::json::object();
        for (size_t k = 0; k < in.layers.layers.size(); ++k) {
            const geometry::PolygonSet& region = in.layers.layers[k].region;
            if (region.empty()) continue;
            AcesParameters layerAces = aces;
            layerAces.direction = scanDirection(region, mOptions.direction);
            AcesDesign design = designAces(layerAces, region);
            plan.layers[k] = planAcesLayer(region, design, in.machine.laserPower, plan.layers[k].z);
            if (mSummary.empty())
                mSummary = {
                    {"target_dose_mJ_per_cm2", design.targetDose * in.beam.efficiency * 100},
                    {"hatch_spacing_um", design.hatchSpacing * 1e3},
                    {"speed_mm_per_s", design.speed},
                    {"edge_offset_um", design.edgeOffset * 1e3},
                    {"ripple", design.ripple},
                    {"wall_level", design.wallLevel},
                    {"scallop_um", design.scallop * 1e3},
                    {"border_loops", design.borderCount}};
        }
        return plan;
    }

    /// {"aces": {target dose, hatch spacing, speed, edge offset, ripple, wall level, scallop,
    /// border loops}} of the first planned layer.
    nlohmann::json summary() const override {
        return mSummary.empty() ? nlohmann::json::object() : nlohmann::json{{"aces", mSummary}};
    }

private:
    LaserPlanOptions mOptions;
    nlohmann::json mSummary = nlohmann::json::object();
};

}  // namespace

void registerAcesPlanner(PlannerRegistry& registry) {
    registry.add({"aces",
                  "ACES hatching (seed 000 Eq. 14-16, App. A-C): parallel lines at the hatch "
                  "spacing and speed that give the target exposure",
                  laserPlanKeys(), [](const ConfigNode& section) {
                      return std::make_unique<AcesPlanner>(readLaserPlanOptions(section));
                  }});
}

}  // namespace vpsim::plan
