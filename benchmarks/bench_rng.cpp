// Random-number throughput: the Vulkan shader vs the CPU path built from the same rng.glsl.
// Prints JSON. Comparison: GPU vs CPU (single thread) in the same run, and the write bandwidth the
// GPU run implies against the ~30 GB/s memory floor of docs/PLATFORM.md.
#include <chrono>
#include <iostream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/rng.h"
#include "vpsim/gpu/rng_stream.h"

int main() {
    using clock = std::chrono::steady_clock;
    const uint32_t streams = 1u << 20, perStream = 16;
    const double numbers = double(streams) * perStream;
    nlohmann::json out{{"benchmark", "rng"}, {"numbers", numbers}};

    auto start = clock::now();
    auto cpu = vpsim::rngStreamsCpu(1u, 0u, streams, perStream, 1u);
    double cpuSeconds = std::chrono::duration<double>(clock::now() - start).count();
    out["cpu_single_thread_numbers_per_second"] = numbers / cpuSeconds;

    try {
        auto context = vpsim::gpu::Context::create();
        double gpuMs = 0;
        vpsim::gpu::rngStreamsGpu(context, 1u, 0u, streams, perStream, 1u, &gpuMs);  // warm-up
        auto gpu = vpsim::gpu::rngStreamsGpu(context, 1u, 0u, streams, perStream, 1u, &gpuMs);
        out["device"] = context->info().name;
        out["gpu_numbers_per_second"] = numbers / (gpuMs * 1e-3);
        out["gpu_over_cpu"] = (numbers / (gpuMs * 1e-3)) / (numbers / cpuSeconds);
        out["gpu_write_bandwidth_GBps"] = numbers * 4 / (gpuMs * 1e-3) / 1e9;
        out["memory_floor_GBps"] = 30.0;
        out["bit_identical"] = gpu == cpu;
    } catch (const vpsim::Error& e) {
        out["gpu_error"] = e.what();
    }
    std::cout << out.dump(2) << std::endl;
    return 0;
}
