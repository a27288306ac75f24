#pragma once
// Private: the shader path of the exposure engine (buffers and kernels kept across layers).
#include <memory>

#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/gpu/context.h"

namespace vpsim::exposure {

struct ExposureEngine::GpuState {
    GpuState(std::shared_ptr<gpu::Context> context, int nx, int ny);
    /// Blurs `deposit` in place (on return it holds B) and updates `running` = B + decay * running.
    /// Returns GPU seconds.
    double blurAndAccumulate(SurfaceGrid& deposit, SurfaceGrid& running, int halfWidth,
                             float sigmaCells, float normX, float normY, float decay);

    std::shared_ptr<gpu::Context> context;
    uint32_t nx, ny;
    gpu::Buffer deposit, pass, blurred, running;
    gpu::Kernel blur, recursion;
};

}  // namespace vpsim::exposure
