#pragma once
/// @file
/// The planner interface: (layer stack, machine, beam, cure law, run context) -> ScanPlan.
/// A planner is created by name from the job's `plan` section (its factory reads and checks its
/// own keys) through a PlannerRegistry filled by registerBuiltins(); adding one is a new file
/// pair plus one registration line (src/pipeline/builtins.cpp). Planners that need the exposure
/// model or the optimisers live in later modules (optimise) and are registered the same way.

#include <memory>

#include <nlohmann/json.hpp>

#include "vpsim/core/registry.h"
#include "vpsim/core/run_context.h"
#include "vpsim/geometry/layer_stack.h"
#include "vpsim/geometry/mesh.h"
#include "vpsim/kernel/fitted_beam.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::cure {
class CureLaw;
}

namespace vpsim::plan {

/// Everything a planner may use. References stay valid during plan().
struct PlannerInputs {
    const geometry::LayerStack& layers;  ///< the sliced part, layer 0 at the platform
    const geometry::Bounds& partBounds;  ///< the part's bounding box (mm)
    const Machine& machine;
    /// The fitted beam: the Monte Carlo fit or a given kernel (laser), or the projector blur
    /// with the resin's penetration depth (DLP).
    const kernel::FittedBeam& beam;
    /// The tabulated Monte Carlo kernel when the job exposes with it, else nullptr.
    const kernel::BeamKernel* table;
    /// The cure law's critical dose (mJ/mm^2): what ACES-style planners aim at.
    double criticalDose;
    /// The cure law itself, for planners in modules that may use it (optimise).
    const cure::CureLaw& cure;
    const RunContext& context;
};

class Planner {
public:
    virtual ~Planner() = default;
    /// The process this planner plans for; the pipeline refuses a job whose machine differs.
    virtual Process process() const = 0;
    /// @throw InputError when the part cannot be planned (with the reason)
    virtual ScanPlan plan(const PlannerInputs& inputs) = 0;
    /// Figures of the last plan() for report.json (e.g. ACES's target dose), an object.
    virtual nlohmann::json summary() const { return nlohmann::json::object(); }
};

using PlannerRegistry = Registry<Planner>;

/// The empty plan of `layers` (each layer's top z, nothing exposed) that planners fill.
ScanPlan emptyPlan(const geometry::LayerStack& layers, const Machine& machine);

}  // namespace vpsim::plan
