#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "support/gpu_test.h"
#include "vpsim/core/error.h"

using namespace vpsim;

TEST_CASE("a Vulkan device is found and describes its limits", "[gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    auto devices = gpu::listDevices();
    REQUIRE(!devices.empty());
    const auto& info = ctx->info();
    CHECK(!info.name.empty());
    CHECK(info.maxStorageBufferRange > 0);
    CHECK(info.maxWorkgroupCount[0] >= 65535u);
    nlohmann::json json = info.toJson();
    CHECK(json["name"] == info.name);
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}

TEST_CASE("buffers round-trip data and refuse sizes beyond device limits", "[gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    gpu::Buffer buffer(ctx, 1000 * sizeof(uint32_t));
    std::vector<uint32_t> values(1000);
    for (uint32_t i = 0; i < 1000; ++i) values[i] = i * 2654435761u;
    buffer.upload(values);
    CHECK(buffer.download<uint32_t>(1000) == values);
    buffer.fill(0xDEADBEEFu);
    CHECK(buffer.download<uint32_t>(3, 4 * 997) == std::vector<uint32_t>(3, 0xDEADBEEFu));
    CHECK_THROWS_AS(buffer.upload(values.data(), 8, 4 * 999), ResourceError);
    uint64_t tooBig = ctx->info().maxStorageBufferRange + 4;
    CHECK_THROWS_WITH(gpu::Buffer(ctx, tooBig), Catch::Matchers::Contains("maxStorageBufferRange"));
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}

TEST_CASE("backend names parse and the CPU backend needs no device") {
    CHECK(gpu::parseBackend("cpu") == gpu::Backend::Cpu);
    CHECK(gpu::contextForBackend(gpu::Backend::Cpu) == nullptr);
    CHECK_THROWS_AS(gpu::parseBackend("cuda"), InputError);
}

TEST_CASE("device selection by name and index, with clear errors", "[gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    auto devices = gpu::listDevices();
    REQUIRE(!devices.empty());
    gpu::ContextOptions options;
    options.validation = true;
    options.device = std::to_string(devices.size());  // one past the end
    CHECK_THROWS_WITH(gpu::Context::create(options), Catch::Matchers::Contains("does not exist"));
    options.device = "no-such-gpu-name";
    CHECK_THROWS_WITH(gpu::Context::create(options), Catch::Matchers::Contains("no-such-gpu-name"));
    options.device = "0";
    auto first = gpu::Context::create(options);
    CHECK(first->info().name == devices[0].name);
    VPSIM_REQUIRE_VALIDATION_CLEAN(first);
}
