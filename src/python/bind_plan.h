#pragma once
// The Python Plan object and the front of a job (part, beam, layers), shared by bind_plan.cpp
// (vpsim.plan, vpsim.export) and bind_exposure.cpp (vpsim.expose).
#include "bind_common.h"
#include "vpsim/pipeline/stages.h"

namespace vpsim::python {

/// A scan plan with the planner's figures (vpsim.Plan).
struct PlanObject {
    plan::ScanPlan plan;
    nlohmann::json summary = nlohmann::json::object();
    std::string strategy;
};

/// What the stages before the plan give.
struct JobFront {
    geometry::Mesh part;
    geometry::Bounds bounds;
    pipeline::BeamResult beam;
    geometry::LayerStack layers;
};
/// Part, estimate check, beam and layers of `job` (the GIL released by the caller).
/// @param planOnly the estimate of the stages up to the plan only
JobFront jobFront(const pipeline::Job& job, const RunContext& context, bool planOnly,
                  bool savedPlan);

}  // namespace vpsim::python
