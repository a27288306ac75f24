// Where the compute shaders run: the exposure shaders on every Vulkan device (lavapipe too, where
// they are within 1.5x of the CPU loops), the photon Monte Carlo shader on hardware GPUs unless
// the run asks for it on a CPU driver as well (--backend vulkan).
#include <catch2/catch.hpp>

#include "support/gpu_test.h"
#include "vpsim/core/run_context.h"
#include "vpsim/pipeline/job.h"
#include "vpsim/pipeline/stages.h"

using namespace vpsim;

TEST_CASE("the exposure shaders run on every Vulkan device, photon Monte Carlo where asked",
          "[gpu][pipeline]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    const pipeline::Job job = pipeline::loadJob(
        std::string(VPSIM_SOURCE_DIR) + "/examples/default.json", pipeline::makeBuiltins());
    pipeline::BeamResult beam;
    beam.beam = kernel::FittedBeam{0.063, 0.037};
    const auto grid = exposure::ExposureGrid::covering(0, 0, 0.5, 0.5, 0.1, 0.01, 5);

    RunContext context;
    context.gpu = ctx;
    CHECK(pipeline::exposureModel(job, grid, beam, context)->usesGpu());
    CHECK(gpu::monteCarloContext(context) == (ctx->info().isHardware() ? ctx : nullptr));
    context.monteCarloOnCpuDevices = true;
    CHECK(gpu::monteCarloContext(context) == ctx);

    context.gpu = nullptr;  // --backend cpu
    CHECK_FALSE(pipeline::exposureModel(job, grid, beam, context)->usesGpu());
    CHECK(gpu::monteCarloContext(context) == nullptr);
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}
