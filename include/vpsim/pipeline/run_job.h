#pragma once
/// @file
/// The main job as a short sequence of stages (stages.h), writing into the output directory:
/// part.stl, kernel/, plan.json, exposure.vdb, reference.vdb, cured.stl, pictures, report.json,
/// index.html. `vpsim plan` runs the stages up to the plan; `vpsim run --plan FILE` starts from a
/// saved or hand-edited plan and gives the same result as a one-shot run.

#include <string>

#include "vpsim/core/run_context.h"
#include "vpsim/pipeline/job.h"
#include "vpsim/pipeline/stages.h"
#include "vpsim/report/job_result.h"

namespace vpsim::pipeline {

struct RunOptions {
    /// A saved plan to expose instead of planning ("" = plan with the job's planner). Read
    /// before anything in the output directory is replaced.
    std::string planFile;
    /// Continue after the last tile of the checkpoint in the output directory (checkpoint.h),
    /// when there is one, exposing its plan instead of planning; a run without it removes any
    /// checkpoint and starts over.
    bool resume = false;
    /// A test hook: stop with an InputError once this many tiles are done and checkpointed
    /// (0: never; over MPI ranks, after the first round that reaches it), as a pre-emption
    /// would.
    int stopAfterTiles = 0;
};

/// Runs `job` into `outDir` (created). @throw InputError, ResourceError, GpuError
report::JobResult runJob(const Job& job, const std::string& outDir, const RunContext& context,
                         const RunOptions& options = {});

/// The stages up to the plan, writing part.stl, kernel/ and plan.json into `outDir`.
PlanResult planJob(const Job& job, const std::string& outDir, const RunContext& context);

}  // namespace vpsim::pipeline
