#include "vpsim/plan/uniform_mask_planner.h"

#include "vpsim/core/checks.h"
#include "vpsim/plan/dlp_masks.h"

namespace vpsim::plan {
namespace {

class UniformMaskPlanner : public Planner {
public:
    UniformMaskPlanner(double dose, bool greyscale) : mDose(dose), mGreyscale(greyscale) {}
    Process process() const override { return Process::Dlp; }

    ScanPlan plan(const PlannerInputs& in) override {
        const geometry::Bounds& b = in.partBounds;
        const geometry::RasterGrid projector = geometry::RasterGrid::covering(
            {b.lo.x, b.lo.y}, {b.hi.x, b.hi.y}, in.machine.pixelPitch, 2);
        ScanPlan plan = emptyPlan(in.layers, in.machine);
        for (size_t k = 0; k < in.layers.layers.size(); ++k)
            if (!in.layers.layers[k].region.empty())
                plan.layers[k].masks.push_back(
                    uniformMask(in.layers.layers[k].region, projector, mDose,
                                mGreyscale ? MaskRasterMode::Greyscale : MaskRasterMode::Binary));
        return plan;
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
                  {{"dose", "dose per layer (default \"78 mJ/cm^2\")"},
                   {"greyscale", "anti-alias edge pixels by their area inside (default false)"}},
                  [](const ConfigNode& section) {
                      return std::make_unique<UniformMaskPlanner>(
                          positiveQuantity(section, "dose", dim::DOSE, 0.78),
                          section.boolean("greyscale", false));
                  }});
}

}  // namespace vpsim::plan
