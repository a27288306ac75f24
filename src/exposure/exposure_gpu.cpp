#include "exposure/exposure_gpu.h"

#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "exposure/exposure_glsl.h"
#include "vpsim/core/error.h"
#include "vpsim/shaders/exposure_blur_spv.h"

namespace vpsim::exposure {
namespace {

constexpr uint32_t GROUP_ROWS = 8;  ///< local_size_y of exposure_blur.comp: source rows per group
constexpr uint32_t GROUP_OUTPUTS = 64;  ///< its outputs per group along a row: 8 invocations of 8
constexpr uint32_t CHUNK = uint32_t(glsl::STENCIL_CHUNK);

uint32_t roundUp(uint32_t n, uint32_t m) {
    return (n + m - 1) / m * m;
}

/// Zero cells left of each source row, and the shader's taps from offset -padding in whole chunks.
uint32_t paddingOf(int halfWidth) {
    return roundUp(uint32_t(halfWidth), 4);
}
uint32_t chunkedTaps(int halfWidth) {
    return roundUp(uint32_t(halfWidth) + paddingOf(halfWidth) + 1, CHUNK);
}

int checkedHalfWidth(const std::vector<float>& taps) {
    const int halfWidth = int(taps.size() / 2);
    if (chunkedTaps(halfWidth) > uint32_t(glsl::EXPOSURE_TAP_BLOCK))
        throw ResourceError(
            "a fitted blur of " + std::to_string(taps.size()) + " taps exceeds the shader's " +
            std::to_string(glsl::EXPOSURE_TAP_BLOCK) + "; use a coarser pitch or the CPU path");
    return halfWidth;
}

/// Row length of a pass's source: the padding, `outputs` to whole groups, and the reach of the
/// last window (its taps past the half-width and the 8 floats it reads ahead).
uint32_t sourceWidth(uint32_t outputs, int halfWidth) {
    return paddingOf(halfWidth) + roundUp(outputs, GROUP_OUTPUTS) +
           roundUp(uint32_t(halfWidth) + CHUNK, 4);
}

gpu::Kernel blurKernel(const std::shared_ptr<gpu::Context>& context, int halfWidth, uint32_t axis) {
    return gpu::Kernel(context, exposure_blur_spv, sizeof exposure_blur_spv,
                       {gpu::Binding::UniformTexels4, gpu::Binding::Uniform, gpu::Binding::Storage},
                       sizeof(glsl::ExposureBlurParams), {{0, uint32_t(halfWidth)}, {1, axis}},
                       GROUP_OUTPUTS / 8);
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
      // The x pass runs along the deposit's rows, the y pass along the pass buffer's (the grid's
      // columns): each source has a row per source row a group reaches.
      depositWidth(sourceWidth(nx, halfWidth)),
      passWidth(sourceWidth(ny, halfWidth)),
      depositSum(size_t(nx) * ny, 0.0f),
      deposit(context, uint64_t(depositWidth) * roundUp(ny, GROUP_ROWS) * sizeof(float)),
      pass(context, uint64_t(passWidth) * roundUp(nx, GROUP_ROWS) * sizeof(float)),
      running(context, uint64_t(nx) * ny * sizeof(float)),
      taps(context, glsl::EXPOSURE_TAP_BLOCK * sizeof(float)),
      alongX(blurKernel(context, halfWidth, 0)),
      alongY(blurKernel(context, halfWidth, 1)) {
    // The padding of both sources is zero once for all: the passes write the grid's cells only.
    // R needs no clearing: the y pass writes every one of its cells before it is read.
    deposit.fill(0u);
    pass.fill(0u);
    std::vector<float> block(glsl::EXPOSURE_TAP_BLOCK, 0.0f);
    const int padding = int(paddingOf(halfWidth));
    for (int o = -halfWidth; o <= halfWidth; ++o)
        block[size_t(o + padding)] = tapValues[size_t(o + halfWidth)];
    taps.upload(block);
}

double ExposureEngine::GpuState::addLayer(const SurfaceGrid& hostDeposit, float decay,
                                          bool restart) {
    const float* d = hostDeposit.values.data();
    float* sum = depositSum.data();
    // Where the host addresses the deposit buffer, S goes into its padded rows as it is made
    // (instead of a second pass copying it there).
    float* padded = static_cast<float*>(deposit.hostMemory());
    const size_t width = nx, stride = depositWidth, padding = paddingOf(halfWidth);
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, ny, 16), [&](const tbb::blocked_range<size_t>& rows) {
            for (size_t j = rows.begin(); j < rows.end(); ++j) {
                float* s = sum + j * width;
                const float* dj = d + j * width;
                for (size_t i = 0; i < width; ++i)
                    s[i] = restart ? dj[i] : glsl::printThroughStep(dj[i], s[i], decay);
                if (padded) std::memcpy(padded + j * stride + padding, s, width * sizeof(float));
            }
        });
    return padded ? blurUploaded() : blurRows(depositSum.data());
}

const float* ExposureEngine::GpuState::runningOnHost() const {
    return static_cast<const float*>(running.hostMemory());
}

double ExposureEngine::GpuState::blur(const SurfaceGrid& map) {
    return blurRows(map.values.data());
}

double ExposureEngine::GpuState::blurRows(const float* source) {
    deposit.uploadRows(source, nx * sizeof(float), ny, nx * sizeof(float),
                       paddingOf(halfWidth) * sizeof(float), depositWidth * sizeof(float));
    return blurUploaded();
}

double ExposureEngine::GpuState::blurUploaded() {
    glsl::ExposureBlurParams x{};
    x.nx = nx;
    x.ny = ny;
    x.sourceWidth = depositWidth;
    x.targetWidth = passWidth;
    x.norm = normX;
    glsl::ExposureBlurParams y = x;
    y.sourceWidth = passWidth;
    y.targetWidth = nx;
    y.norm = normY;
    return 1e-3 * context->submit([&](gpu::Recorder& r) {
        r.dispatch(alongX, {&deposit, &taps, &pass}, &x, roundUp(nx, GROUP_OUTPUTS) / GROUP_OUTPUTS,
                   roundUp(ny, GROUP_ROWS) / GROUP_ROWS);
        r.barrier();
        r.dispatch(alongY, {&pass, &taps, &running}, &y, roundUp(ny, GROUP_OUTPUTS) / GROUP_OUTPUTS,
                   roundUp(nx, GROUP_ROWS) / GROUP_ROWS);
    });
}

void ExposureEngine::GpuState::downloadRunning(SurfaceGrid& host) const {
    running.download(host.values.data(), uint64_t(nx) * ny * sizeof(float));
}

}  // namespace vpsim::exposure
