// A run on many more worker threads than this machine's cores finishes with the figures of a run
// on its own threads. The cured surface's mesher builds each layer in a background task while
// the next slice arrives; a worker waiting inside that layer's loops once took the next slice's
// add(), which waits for the same layer: a hang in most whole runs on a 16-core machine
// (and in 4 runs of this test out of 4, with 64 threads on 2 cores) until the layer's work was
// isolated.
#include <catch2/catch.hpp>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <filesystem>

#include "vpsim/pipeline/run_job.h"

using namespace vpsim;

TEST_CASE("a run on 64 worker threads finishes with the same figures", "[pipeline][threads]") {
    const pipeline::Job job =
        pipeline::loadJob(std::string(VPSIM_SOURCE_DIR) + "/examples/seed001-holes.json",
                          pipeline::makeBuiltins(), {"simulation.outputs=[]"});
    const auto dir = std::filesystem::temp_directory_path() / "vpsim_many_threads";
    const RunContext context{nullptr, false, ""};
    const report::JobResult alone = pipeline::runJob(job, dir.string(), context);

    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 64);
    tbb::task_arena arena(64);
    for (int run = 0; run < 12; ++run) {  // a hang fails the suite at its time limit
        const report::JobResult many =
            arena.execute([&] { return pipeline::runJob(job, dir.string(), context); });
        INFO("run " << run);
        CHECK(many.validation.slices.iou == alone.validation.slices.iou);
        CHECK(many.exposure.maxDose == alone.exposure.maxDose);
        CHECK(many.curedVolume == Approx(alone.curedVolume).epsilon(1e-6));
        CHECK(many.validation.deviation.p95 == alone.validation.deviation.p95);
    }
    std::filesystem::remove_all(dir);
}
