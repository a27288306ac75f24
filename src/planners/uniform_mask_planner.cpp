#include "vpsim/planners/uniform_mask_planner.h"

#include "vpsim/core/progress.h"
#include "vpsim/plan/dlp_masks.h"
#include "vpsim/planners/plan_size.h"

namespace vpsim::planners {
namespace {

class UniformMaskPlanner : public Planner {
public:
    UniformMaskPlanner(double dose, bool greyscale) : mDose(dose), mGreyscale(greyscale) {}
    plan::Process process() const override { return plan::Process::Dlp; }

    plan::ScanPlan plan(const PlannerInputs& in) override {
        const geometry::Bounds& b = in.partBounds;
        const geometry::RasterGrid projector = geometry::RasterGrid::covering(
            {b.lo.x, b.lo.y}, {b.hi.x, b.hi.y}, in.machine.pixelPitch, 2);
        plan::ScanPlan plan = plan::emptyPlan(in.layers, in.machine);
        Progress progress("uniform masks: layers rasterised", in.layers.layers.size());
        for (size_t k = 0; k < in.layers.layers.size(); ++k) {
            if (!in.layers.layers[k].region.empty())
                plan.layers[k].masks.push_back(plan::uniformMask(
                    in.layers.layers[k].region, projector, mDose,
                    mGreyscale ? plan::MaskRasterMode::Greyscale : plan::MaskRasterMode::Binary));
            progress.advance();
        }
        return plan;
    }

    PlanSize estimateSize(const PlanSizeInputs& inputs) const override {
        return maskPlanSize(inputs);
    }

private:
    double mDose;
    bool mGreyscale;
};

}  // namespace

void registerUniformMaskPlanner(PlannerRegistry& registry) {
    registry.add({"uniform-mask",
                  "DLP masks with one dose on every pixel of the layer (seed 001's uniform "
                  "process)",
                  {{quantityKey("dose", dim::DOSE, "78 mJ/cm^2", "dose per layer").positiveOnly(),
                    booleanKey("greyscale", false, "anti-alias edge pixels by their area inside")}},
                  [](const KeyReader& keys) {
                      return std::make_unique<UniformMaskPlanner>(keys.quantity("dose"),
                                                                  keys.boolean("greyscale"));
                  }});
}

}  // namespace vpsim::planners
