#include "vpsim/planners/optimised_mask_planner.h"

#include <cmath>
#include <memory>

#include "vpsim/core/error.h"
#include "vpsim/geometry/raster.h"
#include "vpsim/optimise/dlp/mask_optimiser.h"
#include "vpsim/planners/optimised_mask_review.h"
#include "vpsim/planners/plan_size.h"

namespace vpsim::planners {

KeyTable optimisedMaskKeyTable() {
    return {{
        numberKey("target_conversion", 0.95, "Phi_obj inside the part").in(1e-6, 1.0 - 1e-6),
        numberKey("penalty", 5.5, "a of Eq. 12 at nodes outside the part").in(0.0, 1e6),
        quantityKey("max_dose", dim::DOSE, "130 mJ/cm^2", "d_max per layer").positiveOnly(),
        choiceKey("objective", {"conversion-l2", "geometric"}, "conversion-l2",
                  "conversion-l2: seed 001 Eq. 8; geometric: the cured shape (gel point) with "
                  "margins"),
        choiceKey("bonding", {"own-layer", "run-bottom"}, "own-layer",
                  "Eq. 10 for a run's first exposure"),
        booleanKey("xy_coupling", false,
                   "optimise all pixels jointly through the projector blur on a 3D gel-point "
                   "shape objective, from the column optimum"),
        numberKey("margin", 0.05, "geometric: outside nodes below (1 - margin) Ec").in(0.0, 0.99),
        stringKey("uniform_dose", "mean",
                  "uniform process simulated for the report's comparison: a dose, \"mean\" (the "
                  "plan's mean exposed dose) or 0 (none)"),
        quantityKey("figure_x", dim::LENGTH, nullptr,
                    "x of the column drawn along Z (default: most solid/void changes)"),
        quantityKey("figure_y", dim::LENGTH, nullptr, "y of that column"),
        integerKey("figure_layer", nullptr,
                   "layer whose mask is drawn (default: most distinct grey levels)")
            .in(0, 1e9),
        tableKey("grey_levels",
                 "optional override of machine.grey_levels: [[grey, irradiance], "
                 "...]"),
        quantityKey("exposure_time", dim::TIME, nullptr,
                    "with grey_levels: s per layer (dose = irradiance(grey) x time)")
            .positiveOnly(),
    }};
}

namespace {

/// "mean" -> -1 (the plan's mean exposed dose), else a dose >= 0 (0: no comparison).
double uniformDose(const KeyReader& keys) {
    if (!keys.has("uniform_dose")) return -1.0;
    const nlohmann::json& value = keys.raw("uniform_dose");
    if (value.is_string() && value.get<std::string>() == "mean") return -1.0;
    const ConfigNode& node = keys.node();
    const double dose =
        quantityFromJson(value, dim::DOSE, node.keyPath("uniform_dose"), node.file());
    if (!(dose >= 0.0)) throw keys.error("uniform_dose", "must be a dose >= 0 or \"mean\"");
    return dose;
}

}  // namespace

optimise::DlpMaskPlannerSettings readOptimisedMaskSettings(const KeyReader& keys) {
    optimise::DlpMaskPlannerSettings s;
    s.targetConversion = keys.number("target_conversion");
    s.penalty = keys.number("penalty");
    s.maxDose = keys.quantity("max_dose");
    s.objective = optimise::dlpObjectiveFromName(keys.choice("objective"));
    s.bonding = optimise::bondingFromName(keys.choice("bonding"));
    s.xyCoupling = keys.boolean("xy_coupling");
    s.margin = keys.number("margin");
    s.uniformDose = uniformDose(keys);
    const std::optional<double> x = keys.optionalQuantity("figure_x");
    const std::optional<double> y = keys.optionalQuantity("figure_y");
    s.figureColumnGiven = x || y;
    s.figureX = x.value_or(0.0), s.figureY = y.value_or(0.0);
    if (keys.has("figure_layer")) s.figureLayer = long(keys.integer("figure_layer"));
    return s;
}

namespace {

/// The plan section's projector calibration, or null (then machine.grey_levels is used).
std::shared_ptr<const plan::GreyLevels> greyLevels(const KeyReader& keys) {
    const bool table = keys.has("grey_levels"), time = keys.has("exposure_time");
    if (!table && !time) return nullptr;
    if (!table) throw keys.error("exposure_time", "is given without grey_levels");
    keys.optionalQuantity("exposure_time");  // range-checked here, read with the table
    return std::make_shared<const plan::GreyLevels>(plan::greyLevelsFromConfig(keys.node()));
}

class OptimisedMaskPlanner : public Planner {
public:
    explicit OptimisedMaskPlanner(const KeyReader& keys)
        : mSettings(readOptimisedMaskSettings(keys)), mLevels(greyLevels(keys)) {}
    plan::Process process() const override { return plan::Process::Dlp; }

    plan::ScanPlan plan(const PlannerInputs& in) override {
        const std::optional<cure::ConversionKinetics> kinetics = in.cure.conversionKinetics();
        if (!kinetics)
            throw InputError(
                "planner optimised-mask needs a cure law with conversion kinetics "
                "(K and gel point, e.g. fpp); '" +
                    in.cure.name() + "' has none",
                "", "plan.strategy");
        optimise::DlpProcess process;
        process.rateConstant = kinetics->rateConstant;
        process.gelPoint = kinetics->gelPoint;
        process.penetrationDepth =
            in.cure.hasPenetrationDepth() ? in.cure.penetrationDepth() : in.beam.attenuationLength;
        process.layerThickness = in.machine.layerThickness;
        process.pixelPitch = in.machine.pixelPitch;
        process.blurRadius = in.machine.beamRadius;
        const geometry::Bounds& b = in.partBounds;
        const geometry::RasterGrid grid = geometry::RasterGrid::covering(
            {b.lo.x, b.lo.y}, {b.hi.x, b.hi.y}, in.machine.pixelPitch, 2);
        process.originX = grid.origin.x;
        process.originY = grid.origin.y;
        optimise::DlpLayerStack part;
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
        optimise::DlpMaskPlan result =
            optimise::planOptimisedMasks(part, process, mSettings, *levels);
        mArtefacts = OptimisedMaskArtefacts{};
        mArtefacts.summary = result.summary;
        mArtefacts.figures = std::move(result.figures);
        if (!result.columnPlan.layers.empty()) {  // on the job's layers, as the returned plan
            plan::ScanPlan columns = plan::emptyPlan(in.layers, in.machine);
            for (size_t k = 0; k < columns.layers.size(); ++k)
                columns.layers[k].masks = std::move(result.columnPlan.layers[k].masks);
            mArtefacts.columnPlan = std::move(columns);
        }
        plan::ScanPlan out = plan::emptyPlan(in.layers, in.machine);
        for (size_t k = 0; k < out.layers.size(); ++k)
            out.layers[k].masks = std::move(result.plan.layers[k].masks);
        mArtefacts.planned = true;
        return out;
    }

    nlohmann::json summary() const override {
        return mArtefacts.planned ? mArtefacts.summary : nlohmann::json::object();
    }

    PlanSize estimateSize(const PlanSizeInputs& inputs) const override {
        PlanSize p = maskPlanSize(inputs);
        p.workingBytes = p.maskPixels * 8.0 * 4.0;  // 8 fields of 4 B per pixel per layer
        p.seconds = p.maskPixels * 2e-6;
        if (mSettings.xyCoupling) {
            p.workingBytes += p.maskPixels * 4.0 * 6.0 * 4.0;  // six fields, 2 x 2 cells/pixel
            p.seconds += p.maskPixels * 4.0 * 60 * 4e-8;       // 60 FISTA iterations
            p.detail += ", xy_coupling: six 3D fields at 2 x 2 cells per pixel";
        }
        return p;
    }

    PlanReview review(const PlanReviewInputs& inputs) const override {
        return mArtefacts.planned ? optimisedMaskReview(inputs, mArtefacts) : PlanReview{};
    }

    bool reviewNeedsPlanning() const override { return true; }  // its artefacts

private:
    optimise::DlpMaskPlannerSettings mSettings;
    std::shared_ptr<const plan::GreyLevels> mLevels;
    OptimisedMaskArtefacts mArtefacts;
};

}  // namespace

void registerOptimisedMaskPlanner(PlannerRegistry& registry) {
    registry.add({"optimised-mask",
                  "DLP greyscale masks with a per-pixel, per-layer dose optimised against "
                  "print-through (seed 001 Section 3: exact column optimum; geometric "
                  "objective; xy coupling)",
                  optimisedMaskKeyTable(), [](const KeyReader& keys) {
                      return std::make_unique<OptimisedMaskPlanner>(keys);
                  }});
}

}  // namespace vpsim::planners
