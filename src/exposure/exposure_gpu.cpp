#include "exposure/exposure_gpu.h"

#include "exposure/exposure_glsl.h"
#include "vpsim/core/error.h"
#include "vpsim/shaders/exposure_blur_spv.h"

namespace vpsim::exposure {
namespace {

constexpr uint32_t BLOCK = 8;  ///< outputs per invocation and local size of exposure_blur.comp
constexpr uint32_t SPAN = BLOCK * BLOCK;  ///< a workgroup's outputs along its pass's axis

uint32_t roundUp(uint32_t n, uint32_t m) {
    return (n + m - 1) / m * m;
}

int checkedHalfWidth(const std::vector<float>& taps) {
    if (taps.size() > size_t(glsl::EXPOSURE_TAP_BLOCK))
        throw ResourceError(
            "a fitted blur of " + std::to_string(taps.size()) + " taps exceeds the shader's " +
            std::to_string(glsl::EXPOSURE_TAP_BLOCK) + "; use a coarser pitch or the CPU path");
    return int(taps.size() / 2);
}

gpu::Kernel blurKernel(const std::shared_ptr<gpu::Context>& context, int halfWidth, uint32_t axis) {
    return gpu::Kernel(context, exposure_blur_spv, sizeof exposure_blur_spv,
                       {gpu::Binding::UniformTexels, gpu::Binding::Uniform, gpu::Binding::Storage},
                       sizeof(glsl::ExposureBlurParams), {{0, uint32_t(halfWidth)}, {1, axis}},
                       BLOCK);
}

}  // namespace

ExposureEngine::GpuState::GpuState(std::shared_ptr<gpu::Context> context_, int nx_, int ny_,
                                   const std::vector<float>& tapValues, float normX_, float normY_)
    : context(std::move(context_)),
      nx(uint32_t(nx_)),
      ny(uint32_t(ny_)),
      halfWidth(checkedHalfWidth(tapValues)),
      normX(normX_),
      normY(normY_),
      // Rows as long as the x pass's workgroups reach; the y pass's reach rows to a multiple of
      // SPAN, and the windows read one texel past their last tap: one spare row in each source.
      depositWidth(roundUp(nx, SPAN) + 2 * halfWidth),
      passWidth(roundUp(nx, SPAN)),
      deposit(context, uint64_t(depositWidth) * (roundUp(ny, BLOCK) + 1) * sizeof(float)),
      pass(context, uint64_t(passWidth) * (roundUp(ny, SPAN) + 2 * halfWidth + 1) * sizeof(float)),
      running(context, uint64_t(nx) * ny * sizeof(float)),
      taps(context, glsl::EXPOSURE_TAP_BLOCK * sizeof(float)),
      alongX(blurKernel(context, halfWidth, 0)),
      alongY(blurKernel(context, halfWidth, 1)) {
    // The padding (and the pass buffer's rows above and below the grid) is zero once for all.
    deposit.fill(0u);
    pass.fill(0u);
    running.fill(0u);
    std::vector<float> block(glsl::EXPOSURE_TAP_BLOCK, 0.0f);
    std::copy(tapValues.begin(), tapValues.end(), block.begin());
    taps.upload(block);
}

double ExposureEngine::GpuState::addLayer(const SurfaceGrid& hostDeposit, float decay,
                                          bool restart) {
    deposit.uploadRows(hostDeposit.values.data(), nx * sizeof(float), ny, nx * sizeof(float),
                       halfWidth * sizeof(float), depositWidth * sizeof(float));
    glsl::ExposureBlurParams x{};
    x.nx = nx;
    x.ny = ny;
    x.sourceWidth = depositWidth;
    x.targetWidth = passWidth;
    x.norm = normX;
    x.decay = decay;
    glsl::ExposureBlurParams y = x;
    y.sourceWidth = passWidth;
    y.targetWidth = nx;
    y.norm = normY;
    return 1e-3 * context->submit([&](gpu::Recorder& r) {
        if (restart) r.fill(running, 0u);
        r.dispatch(alongX, {&deposit, &taps, &pass}, &x, roundUp(nx, SPAN) / SPAN,
                   roundUp(ny, BLOCK) / BLOCK);
        r.barrier();
        r.dispatch(alongY, {&pass, &taps, &running}, &y, roundUp(nx, BLOCK) / BLOCK,
                   roundUp(ny, SPAN) / SPAN);
    });
}

void ExposureEngine::GpuState::setRunning(const SurfaceGrid& host) {
    running.upload(host.values);
}

void ExposureEngine::GpuState::downloadRunning(SurfaceGrid& host) const {
    running.download(host.values.data(), uint64_t(nx) * ny * sizeof(float));
}

}  // namespace vpsim::exposure
