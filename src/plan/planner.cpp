#include "vpsim/plan/planner.h"

namespace vpsim::plan {

ScanPlan emptyPlan(const geometry::LayerStack& layers, const Machine& machine) {
    ScanPlan plan;
    plan.machine = machine;
    for (const geometry::Layer& layer : layers.layers)
        plan.layers.push_back({layer.zBottom + layers.layerThickness, {}, {}, {}, {}});
    return plan;
}

}  // namespace vpsim::plan
