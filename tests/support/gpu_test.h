#pragma once
// Shared Vulkan context for GPU tests, created once per test process with the Khronos validation
// layer on. Every GPU test ends with VPSIM_REQUIRE_VALIDATION_CLEAN(ctx): any validation message
// (warning or error) fails the test.

#include <catch2/catch.hpp>

#include <memory>

#include "vpsim/gpu/context.h"

namespace vpsim::test {

inline std::shared_ptr<gpu::Context> gpuContext() {
    static std::shared_ptr<gpu::Context> context = [] {
        gpu::ContextOptions options;
        options.validation = true;
        return gpu::Context::create(options);
    }();
    return context;
}

}  // namespace vpsim::test

#define VPSIM_REQUIRE_VALIDATION_CLEAN(ctx)                                  \
    do {                                                                     \
        INFO("last validation message: " << (ctx)->lastValidationMessage()); \
        REQUIRE((ctx)->validationEnabled());                                 \
        REQUIRE((ctx)->validationMessageCount() == 0);                       \
    } while (0)
