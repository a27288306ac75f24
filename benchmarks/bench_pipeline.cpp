// The main job (benchmarks/jobs/block-10mm.json) on a 10 x 10 x 5 mm block at 10 um voxels (~5e8
// voxels): ACES plan, exposure with print-through, cure, and validation against the model. Prints
// JSON: seconds per stage, peak memory, voxels per second, and the ratio of the
// expose+cure+validate time to the memory-bandwidth floor (touching every voxel's 4 bytes once at
// ~30 GB/s, docs/PLATFORM.md). Target: under 60 s and 4 GiB on the 2-core reference machine. Usage:
// bench_pipeline [--vulkan]
#include <sys/resource.h>

#include <cstring>
#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/gpu/context.h"
#include "vpsim/pipeline/run_job.h"

int main(int argc, char** argv) {
    using namespace vpsim;
    setLogLevel(LogLevel::Warn);
    bool vulkan = argc > 1 && std::strcmp(argv[1], "--vulkan") == 0;
    nlohmann::json out{{"benchmark", "pipeline"}, {"part_mm", {10, 10, 5}}, {"voxel_um", 10}};
    try {
        const pipeline::Builtins builtins = pipeline::makeBuiltins();
        const pipeline::Job job = pipeline::loadJob(
            std::string(VPSIM_SOURCE_DIR) + "/benchmarks/jobs/block-10mm.json", builtins);
        auto dir = std::filesystem::temp_directory_path() / "vpsim_bench_pipeline";
        RunContext context;
        if (vulkan) context.gpu = gpu::Context::create();
        context.shadersOnCpuDevices = vulkan;
        nlohmann::json report = report::toJson(pipeline::runJob(job, dir.string(), context));
        const auto& grid = report["exposure"]["grid"];
        double voxels = grid[0].get<double>() * grid[1].get<double>() * grid[2].get<double>();
        const auto& stages = report["stage_seconds"];
        double core = stages["expose"].get<double>() + stages["cure"].get<double>() +
                      stages["validate"].get<double>();
        rusage usage{};
        getrusage(RUSAGE_SELF, &usage);
        out["backend"] = report["backend"];
        out["voxels"] = voxels;
        out["stage_seconds"] = stages;
        out["expose_cure_validate_seconds"] = core;
        out["voxels_per_second"] = voxels / core;
        out["memory_floor_seconds"] = voxels * 4 / 30e9;
        out["ratio_to_memory_floor"] = core / (voxels * 4 / 30e9);
        out["peak_memory_GiB"] = usage.ru_maxrss / 1024.0 / 1024.0;
        out["targets"] = {{"seconds", 60}, {"memory_GiB", 4}};
        out["iou"] = report["iou"];
        std::filesystem::remove_all(dir);
    } catch (const Error& e) {
        out["error"] = e.what();
    }
    std::cout << out.dump(2) << std::endl;
    return 0;
}
