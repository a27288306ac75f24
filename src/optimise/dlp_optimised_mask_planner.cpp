#include "vpsim/optimise/dlp_optimised_mask_planner.h"

#include <memory>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/cure/fpp_law.h"
#include "vpsim/geometry/raster.h"
#include "vpsim/optimise/dlp_mask_planner.h"

namespace vpsim::optimise {
namespace {

class OptimisedMaskPlanner : public plan::Planner {
public:
    OptimisedMaskPlanner(DlpMaskPlannerSettings settings,
                         std::shared_ptr<const plan::GreyLevels> levels)
        : mSettings(settings), mLevels(std::move(levels)) {}
    plan::Process process() const override { return plan::Process::Dlp; }

    plan::ScanPlan plan(const plan::PlannerInputs& in) override {
        const auto* fpp = dynamic_cast<const cure::FppLaw*>(&in.cure);
        if (!fpp)
            throw InputError("planner optimised-mask needs the fpp cure law (K and gel point)", "",
                             "plan.strategy");
        DlpProcess process;
        process.rateConstant = fpp->rateConstant();
        process.gelPoint = fpp->gelPoint();
        process.penetrationDepth =
            fpp->hasPenetrationDepth() ? fpp->penetrationDepth() : in.beam.attenuationLength;
        process.layerThickness = in.machine.layerThickness;
        process.pixelPitch = in.machine.pixelPitch;
        process.blurRadius = in.machine.beamRadius;
        const geometry::Bounds& b = in.partBounds;
        const geometry::RasterGrid grid = geometry::RasterGrid::covering(
            {b.lo.x, b.lo.y}, {b.hi.x, b.hi.y}, in.machine.pixelPitch, 2);
        process.originX = grid.origin.x;
        process.originY = grid.origin.y;
        DlpLayerStack part;
        part.width = grid.width, part.height = grid.height;
        for (const auto& layer : in.layers.layers)
            part.layers.push_back(layer.region.empty()
                                      ? std::vector<uint8_t>(grid.pixelCount(), 0)
                                      : geometry::rasterizeBinary(layer.region, grid));
        // The machine's calibration (machine.grey_levels), else one given in the plan section.
        const auto& levels = in.machine.greyLevels ? in.machine.greyLevels : mLevels;
        if (!levels)
            throw InputError(
                "planner optimised-mask needs the projector's grey levels (machine.grey_levels "
                "and machine.exposure_time)",
                "", "machine.grey_levels");
        DlpMaskPlan result = planOptimisedMasks(part, process, mSettings, *levels);
        mSummary = result.summary;
        mSummary["figures"] = std::move(result.figures);  // the pipeline draws and removes it
        mColumnPlan = std::move(result.columnPlan);
        if (!mColumnPlan.layers.empty()) {  // on the job's layers, as the returned plan
            plan::ScanPlan columns = plan::emptyPlan(in.layers, in.machine);
            for (size_t k = 0; k < columns.layers.size(); ++k)
                columns.layers[k].masks = std::move(mColumnPlan.layers[k].masks);
            mColumnPlan = std::move(columns);
        }
        plan::ScanPlan out = plan::emptyPlan(in.layers, in.machine);
        for (size_t k = 0; k < out.layers.size(); ++k)
            out.layers[k].masks = std::move(result.plan.layers[k].masks);
        return out;
    }

    nlohmann::json summary() const override { return mSummary; }
    const plan::ScanPlan* columnPlan() const {
        return mColumnPlan.layers.empty() ? nullptr : &mColumnPlan;
    }

private:
    DlpMaskPlannerSettings mSettings;
    std::shared_ptr<const plan::GreyLevels> mLevels;
    nlohmann::json mSummary = nlohmann::json::object();
    plan::ScanPlan mColumnPlan;
};

}  // namespace

const plan::ScanPlan* optimisedMaskColumnPlan(const plan::Planner& planner) {
    const auto* p = dynamic_cast<const OptimisedMaskPlanner*>(&planner);
    return p ? p->columnPlan() : nullptr;
}

void registerOptimisedMaskPlanner(plan::PlannerRegistry& registry) {
    registry.add(
        {"optimised-mask",
         "DLP greyscale masks with a per-pixel, per-layer dose optimised against print-through "
         "(seed 001 Section 3: exact column optimum; geometric objective; xy coupling)",
         {{"target_conversion", "Phi_obj inside the part (default 0.95)"},
          {"penalty", "a of Eq. 12 at nodes outside the part (default 5.5)"},
          {"max_dose", "d_max per layer (default \"130 mJ/cm^2\")"},
          {"objective", "conversion-l2 (default) | geometric"},
          {"bonding", "Eq. 10 for a run's first exposure: own-layer (default) | run-bottom"},
          {"xy_coupling",
           "optimise all pixels jointly through the projector blur on a 3D gel-point shape "
           "objective, from the column optimum (default false)"},
          {"margin", "geometric: outside nodes below (1 - margin) Ec (default 0.05)"},
          {"uniform_dose",
           "uniform process simulated for the report's comparison: a dose, \"mean\" (the "
           "plan's mean exposed dose, default) or 0 (none)"},
          {"figure_x", "x of the column drawn along Z (mm; default: most solid/void changes)"},
          {"figure_y", "y of that column (mm)"},
          {"figure_layer", "layer whose mask is drawn (default: most distinct grey levels)"},
          {"grey_levels", "optional override of machine.grey_levels: [[grey, irradiance], ...]"},
          {"exposure_time", "with grey_levels: s per layer (dose = irradiance(grey) x time)"}},
         [](const ConfigNode& section) {
             std::shared_ptr<const plan::GreyLevels> levels;
             if (section.has("grey_levels"))
                 levels =
                     std::make_shared<const plan::GreyLevels>(plan::greyLevelsFromConfig(section));
             return std::make_unique<OptimisedMaskPlanner>(
                 dlpMaskPlannerSettingsFromConfig(section), std::move(levels));
         }});
}

}  // namespace vpsim::optimise
