#pragma once
/// @file
/// The planner interface: (layer stack, machine, beam, cure law, run context) -> ScanPlan.
/// A planner is created by name from the job's `plan` section (its factory reads and checks its
/// own keys) through a PlannerRegistry filled by registerBuiltins(); adding one is a new file
/// pair plus one registration line (src/pipeline/builtins.cpp). Planners that need the exposure
/// model or the optimisers live in later modules (optimise) and are registered the same way.

#include <memory>
#include <optional>
#include <string>

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

/// What a job's estimate (pipeline/estimate.h) knows before the kernel is computed or the part
/// sliced: enough to size a plan and a planner's working set.
struct PlanSizeInputs {
    const geometry::Bounds& partBounds;  ///< mm
    double partVolume;                   ///< mm^3
    int layers;                          ///< layers the part is sliced into
    const Machine& machine;
    double beamRadius;              ///< mm, an upper guess of the fitted beam's We3D
    double penetrationDepth;        ///< mm, the cure law's (0 when it has none)
    const nlohmann::json& options;  ///< the job's plan section as written
    double contourVertices;         ///< slice contour vertices of all layers
};

/// A planner's share of a job's estimate, bytes and seconds (order of magnitude).
struct PlanSize {
    double planBytes = 0;     ///< the ScanPlan it returns (vectors, points, masks)
    double workingBytes = 0;  ///< what it holds while planning, on top of the plan
    double jsonBytes = 0;     ///< plan.json's nlohmann::json tree while it is written
    double fileBytes = 0;     ///< plan.json on disk
    double maskPixels = 0;    ///< mask pixels of all layers (DLP), for the exporters' files
    double elements = 0;      ///< vectors + points + moves, or mask pixels
    double seconds = 0;
    std::string detail;  ///< how the figures follow from the inputs, for the estimate's table
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
    /// The plan's size and the planner's working set, for the job's up-front estimate. The
    /// default (nullopt) lets the pipeline use its term for the strategy
    /// (src/pipeline/planner_estimates.cpp) or, for a strategy it does not know, a generic one
    /// by process; a planner with a large working set overrides this in its own file.
    virtual std::optional<PlanSize> estimateSize(const PlanSizeInputs& inputs) const {
        (void)inputs;
        return std::nullopt;
    }
};

using PlannerRegistry = Registry<Planner>;

/// The empty plan of `layers` (each layer's top z, nothing exposed) that planners fill.
ScanPlan emptyPlan(const geometry::LayerStack& layers, const Machine& machine);

}  // namespace vpsim::plan
