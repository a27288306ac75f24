#pragma once
// Private to the report module: the job's Monte Carlo beam kernel, cached by its inputs.
#include <memory>

#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/report/job.h"
#include "vpsim/report/run_job.h"

namespace vpsim::report {

/// Runs (or loads from the cache) the kernel of the job's material and beam.
kernel::BeamKernel monteCarloKernel(const Job& job, const std::shared_ptr<gpu::Context>& context,
                                    bool& fromCache);

}  // namespace vpsim::report
