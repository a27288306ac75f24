#include "vpsim/planners/aces_planner.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/progress.h"
#include "vpsim/plan/machine/laser_limits.h"
#include "vpsim/planners/laser_plan_options.h"
#include "vpsim/planners/plan_size.h"

namespace vpsim::planners {
namespace {

/// The layers around layer k for the contour rule: those above within the reach of their
/// print-through (exp(-dz/De3D) > 1e-3), nearest first, and the one below.
plan::AcesStack stackAround(const std::vector<geometry::Layer>& layers,
                            const std::vector<double>& offsets, size_t k,
                            double attenuationLength) {
    plan::AcesStack stack;
    for (size_t j = k + 1; j < layers.size(); ++j) {
        const double distance = layers[j].z - layers[k].z;
        if (!(distance > 0) || distance > 6.9 * attenuationLength) break;
        if (!layers[j].region.empty())
            stack.above.push_back({&layers[j].region, distance, offsets[j]});
    }
    if (k > 0 && !layers[k - 1].region.empty() && layers[k].z > layers[k - 1].z)
        stack.below =
            plan::AcesNeighbour{&layers[k - 1].region, layers[k].z - layers[k - 1].z, 0.0};
    return stack;
}

class AcesPlanner : public Planner {
public:
    explicit AcesPlanner(LaserPlanOptions options) : mOptions(options) {}
    plan::Process process() const override { return plan::Process::Laser; }

    plan::ScanPlan plan(const PlannerInputs& in) override {
        const plan::AcesParameters aces =
            acesParameters(mOptions, in.beam, in.machine, in.criticalDose);
        checkLaserDose(aces, in.machine);
        plan::ScanPlan plan = plan::emptyPlan(in.layers, in.machine);
        mSummary = nlohmann::json::object();
        const auto& layers = in.layers.layers;
        std::vector<double> offsets(layers.size(), 0.0);
        // Top down, so the contour rule sees what the layers above (designed already) send in.
        Progress progress("ACES: layers hatched, top down", layers.size());
        for (size_t k = layers.size(); k-- > 0;) {
            const geometry::PolygonSet& region = layers[k].region;
            if (region.empty()) {
                progress.advance();
                continue;
            }
            plan::AcesParameters layerAces = aces;
            layerAces.direction = plan::scanDirection(region, mOptions.direction);
            const plan::AcesStack stack = stackAround(layers, offsets, k, aces.attenuationLength);
            plan::AcesDesign design = plan::designAces(layerAces, region, &stack);
            offsets[k] = design.edgeOffset;
            // The power that puts the hatch at the process speed along its direction (or the
            // laser's full power, slower, where that is not enough).
            const double lineEnergy = design.targetDose * design.hatchSpacing;  // mJ/mm
            const double c = std::cos(design.direction), s = std::sin(design.direction);
            const double power = std::min(
                in.machine.laserPower,
                lineEnergy * plan::markSpeedLimit(0, 0, c, s, in.machine.scanner.process.speed));
            design.speed = power / lineEnergy;
            plan.layers[k] = plan::planAcesLayer(region, design, power, plan.layers[k].z);
            mSummary = {// ends with the lowest planned layer's (the steadiest wall)
                        {"target_dose_mJ_per_cm2", design.targetDose * in.beam.efficiency * 100},
                        {"hatch_spacing_um", design.hatchSpacing * 1e3},
                        {"speed_mm_per_s", design.speed},
                        {"power_mW", design.speed * design.targetDose * design.hatchSpacing},
                        {"edge_offset_um", design.edgeOffset * 1e3},
                        {"ripple", design.ripple},
                        {"wall_level", design.wallLevel},
                        {"scallop_um", design.scallop * 1e3},
                        {"border_loops", design.borderCount}};
            progress.advance();
        }
        if (!mSummary.empty()) mSummary = {{"aces", mSummary}};
        mSummary.update(fitLaserPlan(plan, aces, in.machine, 0.0));
        return plan;
    }

    PlanSize estimateSize(const PlanSizeInputs& inputs) const override {
        return laserPlanSize(inputs, mOptions.aces.borderCount);
    }
    plan::OrderMethod partOrder() const override { return mOptions.order; }

    /// {"aces": {target dose, hatch spacing, speed, power, edge offset, ripple, wall level,
    /// scallop, border loops}} of the lowest planned layer, and {"laser": the fit to the machine's
    /// limits}.
    nlohmann::json summary() const override { return mSummary; }

private:
    LaserPlanOptions mOptions;
    nlohmann::json mSummary = nlohmann::json::object();
};

}  // namespace

plan::ScanPlan acesStackPlan(const PlannerInputs& inputs, const LaserPlanOptions& options,
                             nlohmann::json* summary) {
    AcesPlanner aces(options);
    plan::ScanPlan plan = aces.plan(inputs);
    if (summary) *summary = aces.summary();
    return plan;
}

void registerAcesPlanner(PlannerRegistry& registry) {
    registry.add({"aces",
                  "ACES hatching (seed 000 Eq. 14-16, App. A-C): parallel lines at the hatch "
                  "spacing and speed that give the target exposure",
                  laserPlanKeyTable(), [](const KeyReader& keys) {
                      return std::make_unique<AcesPlanner>(readLaserPlanOptions(keys));
                  }});
}

}  // namespace vpsim::planners
