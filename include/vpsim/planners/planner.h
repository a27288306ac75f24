#pragma once
/// @file
/// The planner interface: (layer stack, machine, beam, cure law, run context) -> ScanPlan, plus
/// what a planner owns about itself: its key table (at registration), its share of the job's
/// estimate (estimateSize), the parts order of its trajectories (partOrder) and its work after
/// the run has exposed the plan (review: figures, comparisons, metrics for the report).
/// A planner is created by name from the job's `plan` section through a PlannerRegistry filled
/// by registerBuiltins(); adding one is a new file pair plus one registration line
/// (src/pipeline/builtins.cpp): the pipeline calls only this interface.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/core/registry.h"
#include "vpsim/core/run_context.h"
#include "vpsim/cure/cure_law.h"
#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/layer_stack.h"
#include "vpsim/geometry/mesh.h"
#include "vpsim/kernel/fitted_beam.h"
#include "vpsim/plan/machine/part_order.h"
#include "vpsim/plan/scan_plan.h"
#include "vpsim/report/job_result.h"
#include "vpsim/validate/feature_probe.h"
#include "vpsim/validate/slice_validator.h"

namespace vpsim::optimise {
class ExposureErrorSink;
}

namespace vpsim::planners {

/// Everything a planner may use. References stay valid during plan().
struct PlannerInputs {
    const geometry::LayerStack& layers;  ///< the sliced part, layer 0 at the platform
    const geometry::Bounds& partBounds;  ///< the part's bounding box (mm)
    const plan::Machine& machine;
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
    /// The part's mesh when the pipeline has it (planners that judge the plan in 3D slice it at
    /// their own heights), else nullptr: the layers' regions stand for it.
    const geometry::Mesh* part = nullptr;
};

/// What a job's estimate (pipeline/estimate.h) knows before the kernel is computed or the part
/// sliced: enough to size a plan and a planner's working set (the planner adds its own settings).
struct PlanSizeInputs {
    const geometry::Bounds& partBounds;  ///< mm
    double partVolume;                   ///< mm^3
    int layers;                          ///< layers the part is sliced into
    const plan::Machine& machine;
    double beamRadius;        ///< mm, an upper guess of the fitted beam's We3D
    double penetrationDepth;  ///< mm, the cure law's (0 when it has none)
    double contourVertices;   ///< slice contour vertices of all layers
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

/// What a planner's review may use once the run has exposed, cured and validated its plan.
struct PlanReviewInputs {
    const geometry::Mesh& part;
    const geometry::LayerStack& layers;
    const geometry::Bounds& partBounds;
    const plan::ScanPlan& plan;  ///< the plan the run exposed (planned now, or a saved one)
    const plan::Machine& machine;
    const kernel::FittedBeam& beam;
    const cure::CureLaw& cure;
    const std::vector<validate::FeatureProbe>& features;
    const validate::FeatureMeasurements& featureResults;  ///< the run's, of the exposed plan
    double voxel;                                         ///< the simulation's x-y cell, mm
    double voxelHeight;                                   ///< mm
    /// The run's exposure model, to expose other plans (a comparison) on the same grid.
    exposure::ExposureModel& model;
    const validate::SliceValidationSummary& validation;  ///< of the plan the run exposed
    const std::string& strategy;                         ///< the registered name, for captions
    const std::string& outDir;                           ///< where figures go
    bool figures;  ///< simulation.outputs asks for figures (else the review writes none)
    /// The exposure error the run took from its slices (laserExposureErrorSink), or nullptr:
    /// the laser review then exposes the plan again on the planning grid.
    optimise::ExposureErrorSink* exposureError = nullptr;
};

/// What a review adds to the run's report.
struct PlanReview {
    /// Merged (JSON merge patch) into report.json's top level, next to the planner's summary()
    /// (e.g. "layer_exposure_error", or figures added to the planner's own object).
    nlohmann::json report = nlohmann::json::object();
    /// Tables and figures (files the review wrote into outDir) for index.html.
    std::vector<report::ReportSection> sections;
};

class Planner {
public:
    virtual ~Planner() = default;
    /// The process this planner plans for; the pipeline refuses a job whose machine differs.
    virtual plan::Process process() const = 0;
    /// @throw InputError when the part cannot be planned (with the reason)
    virtual plan::ScanPlan plan(const PlannerInputs& inputs) = 0;
    /// Figures of the last plan() for report.json (e.g. ACES's target dose), an object.
    virtual nlohmann::json summary() const { return nlohmann::json::object(); }
    /// The plan's size and the planner's working set, for the job's up-front estimate. The
    /// default is the generic term of the process (plan_size.h); a planner with a larger
    /// working set overrides it with its own settings.
    virtual PlanSize estimateSize(const PlanSizeInputs& inputs) const;
    /// How the trajectories order each layer's parts (laser; `order` key of laser planners).
    virtual plan::OrderMethod partOrder() const { return plan::OrderMethod::Auto; }
    /// Work after the run's exposure, for the report. The default gives every laser plan the
    /// seed's exposure-error metric (laser_exposure_review.h) and DLP plans nothing.
    /// @throw InputError when a figure cannot be written
    virtual PlanReview review(const PlanReviewInputs& inputs) const;
    /// Whether review() needs what plan() kept besides the plan and summary(): a resumed run
    /// (checkpoint.h) then plans again instead of exposing the checkpoint's plan.
    virtual bool reviewNeedsPlanning() const { return false; }
};

using PlannerRegistry = Registry<Planner>;

}  // namespace vpsim::planners
