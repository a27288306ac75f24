#pragma once
// Shared Vulkan context for GPU tests, created once per test process with the Khronos validation
// layer on. Every GPU test starts with VPSIM_GPU_CONTEXT_OR_SKIP(ctx) and ends with
// VPSIM_REQUIRE_VALIDATION_CLEAN(ctx): any validation message (warning or error) fails the test.
//
// Without a Vulkan device (no loader instance, or an instance with no physical device) a GPU test
// is skipped: Catch2 v2 has no SKIP, so the test prints a warning "skipped: no Vulkan device ..."
// (shown by the console reporter with the test's name) and returns, and the suite still passes.
// CI machines that must have a device (lavapipe) set VPSIM_REQUIRE_GPU=1 to make a missing device
// a failure instead. A device that exists but cannot be opened is always a failure.

#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "vpsim/core/error.h"
#include "vpsim/gpu/context.h"

namespace vpsim::test {

/// The shared context, or nullptr with the reason when no Vulkan device exists.
struct GpuAvailability {
    std::shared_ptr<gpu::Context> context;
    std::string whyNot;  ///< "" when context is set
};

/// @throw GpuError (failing the calling test) when a device is listed but cannot be opened
inline const GpuAvailability& gpuAvailability() {
    static const GpuAvailability availability = [] {
        GpuAvailability a;
        try {
            if (gpu::listDevices().empty()) {
                a.whyNot = "the Vulkan instance lists no physical device";
                return a;
            }
        } catch (const GpuError& e) {
            a.whyNot = e.what();
            return a;
        }
        gpu::ContextOptions options;
        options.validation = true;
        a.context = gpu::Context::create(options);
        return a;
    }();
    return availability;
}

/// The shared validated context; nullptr when no Vulkan device exists.
inline std::shared_ptr<gpu::Context> gpuContext() {
    return gpuAvailability().context;
}

/// A second validated context on the same device whose buffers move through staging copies, as
/// a discrete GPU's do (ContextOptions::stagedTransfers): on lavapipe the shared context maps
/// device memory and never takes that path. nullptr when no Vulkan device exists.
inline std::shared_ptr<gpu::Context> stagedGpuContext() {
    static const std::shared_ptr<gpu::Context> staged = []() -> std::shared_ptr<gpu::Context> {
        if (!gpuContext()) return nullptr;
        gpu::ContextOptions options;
        options.validation = true;
        options.stagedTransfers = true;
        return gpu::Context::create(options);
    }();
    return staged;
}

/// True when VPSIM_REQUIRE_GPU=1: a missing device fails GPU tests instead of skipping them.
inline bool gpuRequired() {
    const char* value = std::getenv("VPSIM_REQUIRE_GPU");
    return value && std::strcmp(value, "1") == 0;
}

}  // namespace vpsim::test

/// Declares `ctx`, the shared context; without a Vulkan device prints why and returns from the
/// test (or fails it when VPSIM_REQUIRE_GPU=1).
#define VPSIM_GPU_CONTEXT_OR_SKIP(ctx)                                                        \
    auto ctx = ::vpsim::test::gpuContext();                                                   \
    if (!ctx) {                                                                               \
        const std::string vpsimWhyNot = ::vpsim::test::gpuAvailability().whyNot;              \
        if (::vpsim::test::gpuRequired())                                                     \
            FAIL("no Vulkan device and VPSIM_REQUIRE_GPU=1: " << vpsimWhyNot);                \
        WARN("skipped: no Vulkan device (" << vpsimWhyNot                                     \
                                           << "); VPSIM_REQUIRE_GPU=1 makes this a failure"); \
        return;                                                                               \
    }                                                                                         \
    static_assert(true, "require a semicolon")

#define VPSIM_REQUIRE_VALIDATION_CLEAN(ctx)                                  \
    do {                                                                     \
        INFO("last validation message: " << (ctx)->lastValidationMessage()); \
        REQUIRE((ctx)->validationEnabled());                                 \
        REQUIRE((ctx)->validationMessageCount() == 0);                       \
    } while (0)
