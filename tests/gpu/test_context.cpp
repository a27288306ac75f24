#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "support/gpu_test.h"
#include "vpsim/core/error.h"
#include "vpsim/shaders/layout_probe_spv.h"

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

// The engines of a tiled run specialise their shader alike and share one pipeline; a kernel is
// made again once nobody holds it.
TEST_CASE("kernels of the same arguments are shared while someone holds them", "[gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    const std::vector<gpu::Binding> bindings(4, gpu::Binding::Storage);
    auto make = [&](const std::shared_ptr<gpu::Context>& context, uint32_t constant) {
        return gpu::Kernel::shared(context, layout_probe_spv, sizeof layout_probe_spv, bindings, 0,
                                   {{0, constant}}, 1);
    };
    auto first = make(ctx, 1);
    CHECK(make(ctx, 1) == first);
    auto other = make(ctx, 2);  // another specialisation
    CHECK(other != first);
    auto staged = test::stagedGpuContext();  // another context
    CHECK(make(staged, 1) != first);
    std::weak_ptr<const gpu::Kernel> held = first;
    first.reset();
    CHECK(held.expired());
    auto again = make(ctx, 1);
    CHECK(again);
    CHECK(again->bindingCount() == 4);
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}

// A discrete GPU's buffers are not mapped: every transfer goes through the buffer's staging
// copy, kept between transfers and grown when a larger one comes.
TEST_CASE("buffers round-trip rows through staging copies", "[gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(shared);
    const auto ctx = test::stagedGpuContext();
    REQUIRE(ctx);
    gpu::Buffer buffer(ctx, 64 * 20 * sizeof(float));
    CHECK(buffer.hostMemory() == nullptr);
    std::vector<float> rows(40 * 10), back(40 * 10, -1.0f);
    for (size_t i = 0; i < rows.size(); ++i) rows[i] = float(i) * 0.5f;
    buffer.fill(0);
    // 10 rows of 40 floats into rows of 64 from row 3, column 5; then back out, twice (the
    // staging copy reused), then a whole-buffer transfer (the staging copy grown).
    for (int pass = 0; pass < 2; ++pass) {
        buffer.uploadRows(rows.data(), 40 * 4, 10, 40 * 4, (3 * 64 + 5) * 4, 64 * 4);
        buffer.downloadRows(back.data(), 40 * 4, 10, (3 * 64 + 5) * 4, 64 * 4, 40 * 4);
        CHECK(back == rows);
    }
    const std::vector<float> whole = buffer.download<float>(64 * 20);
    CHECK(whole[3 * 64 + 4] == 0.0f);
    CHECK(whole[3 * 64 + 5] == rows[0]);
    CHECK(whole[12 * 64 + 44] == rows.back());
    CHECK(whole[12 * 64 + 45] == 0.0f);
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}

// A buffer's host mirror: the buffer itself where mapped, else its staging copy, moved inside a
// submission (Recorder::toDevice, toHost) with the work that uses it; on both contexts.
TEST_CASE("host mirrors move with the work in one submission", "[gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(shared);
    for (const auto& ctx : {shared, test::stagedGpuContext()}) {
        gpu::Buffer a(ctx, 100 * sizeof(uint32_t)), b(ctx, 100 * sizeof(uint32_t));
        a.fill(3u);
        auto* mirrorA = static_cast<uint32_t*>(a.hostMirror());
        auto* mirrorB = static_cast<uint32_t*>(b.hostMirror());
        CHECK((mirrorA == a.hostMemory()) == (a.hostMemory() != nullptr));
        CHECK(mirrorA[0] == 3u);
        CHECK(mirrorA[99] == 3u);  // the buffer's contents when first made
        for (uint32_t i = 0; i < 100; ++i) mirrorA[i] = 7 * i + 1;
        ctx->submit([&](gpu::Recorder& r) {
            r.toDevice(a);
            r.fill(b, 0u);
            r.barrier();
            r.copy(a, b, 60 * sizeof(uint32_t), 0, 40 * sizeof(uint32_t));
            r.toHost(b);
        });
        CHECK(mirrorB[39] == 0u);
        CHECK(mirrorB[40] == 1u);
        CHECK(mirrorB[99] == 7u * 59 + 1);
        CHECK(b.download<uint32_t>(1, 41 * sizeof(uint32_t))[0] == 8u);
        VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
    }
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
