#include "exposure/exposure_gpu.h"

#include "exposure/exposure_glsl.h"
#include "vpsim/shaders/exposure_blur_spv.h"
#include "vpsim/shaders/exposure_recursion_spv.h"

namespace vpsim::exposure {

ExposureEngine::GpuState::GpuState(std::shared_ptr<gpu::Context> context_, int nx_, int ny_)
    : context(std::move(context_)),
      nx(uint32_t(nx_)),
      ny(uint32_t(ny_)),
      deposit(context, uint64_t(nx) * ny * sizeof(float)),
      pass(context, uint64_t(nx) * ny * sizeof(float)),
      blurred(context, uint64_t(nx) * ny * sizeof(float)),
      running(context, uint64_t(nx) * ny * sizeof(float)),
      blur(context, exposure_blur_spv, sizeof exposure_blur_spv, 2,
           sizeof(glsl::ExposureBlurParams), {}, 64),
      recursion(context, exposure_recursion_spv, sizeof exposure_recursion_spv, 2,
                sizeof(glsl::ExposureRecursionParams), {}, 64) {
    running.fill(0u);
}

double ExposureEngine::GpuState::blurAndAccumulate(SurfaceGrid& hostDeposit,
                                                   SurfaceGrid& hostRunning, int halfWidth,
                                                   float sigmaCells, float normX, float normY,
                                                   float decay) {
    deposit.upload(hostDeposit.values);
    running.upload(hostRunning.values);
    glsl::ExposureBlurParams alongX{};
    alongX.nx = nx;
    alongX.ny = ny;
    alongX.axis = 0;
    alongX.halfWidth = halfWidth;
    alongX.sigmaCells = sigmaCells;
    alongX.norm = normX;
    glsl::ExposureBlurParams alongY = alongX;
    alongY.axis = 1;
    alongY.norm = normY;
    glsl::ExposureRecursionParams step{};
    step.count = nx * ny;
    step.decay = decay;
    const uint64_t cells = uint64_t(nx) * ny;
    double ms = context->submit([&](gpu::Recorder& r) {
        r.dispatch1D(blur, {&deposit, &pass}, &alongX, cells);
        r.barrier();
        r.dispatch1D(blur, {&pass, &blurred}, &alongY, cells);
        r.barrier();
        r.dispatch1D(recursion, {&blurred, &running}, &step, cells);
    });
    blurred.download(hostDeposit.values.data(), cells * sizeof(float));
    running.download(hostRunning.values.data(), cells * sizeof(float));
    return ms * 1e-3;
}

}  // namespace vpsim::exposure
