#include "exposure/exposure_gpu.h"

#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "exposure/exposure_glsl.h"
#include "vpsim/core/error.h"
#include "vpsim/shaders/exposure_blur_spv.h"

namespace vpsim::exposure {
namespace {

constexpr uint32_t GROUP_OUTPUTS = 64;  ///< cells along x per group of exposure_blur.comp: 8 x 8
constexpr uint32_t CHUNK = uint32_t(glsl::STENCIL_CHUNK);
constexpr uint32_t STEPS = uint32_t(glsl::EXPOSURE_BLUR_STEPS);

uint32_t roundUp(uint32_t n, uint32_t m) {
    return (n + m - 1) / m * m;
}

/// Zero cells left of each source row; the shader's taps start at offset -padding.
uint32_t paddingOf(int halfWidth) {
    return roundUp(uint32_t(halfWidth), 4);
}

/// Steps before a strip's first output row: its 2 halfWidth open rows. Grid row j lies in source
/// row j + halfWidth.
uint32_t leadOf(int halfWidth) {
    return 2 * uint32_t(halfWidth);
}

bool shaderTakes(int halfWidth) {
    static_assert(2 * glsl::EXPOSURE_BLUR_MAX_HALF_WIDTH + CHUNK <= glsl::EXPOSURE_TAP_BLOCK,
                  "the widest blur's chunked taps fit the tap block");
    return halfWidth >= 1 && halfWidth <= glsl::EXPOSURE_BLUR_MAX_HALF_WIDTH;
}

int checkedHalfWidth(const std::vector<float>& taps) {
    const int halfWidth = int(taps.size() / 2);
    if (!shaderTakes(halfWidth))
        throw ResourceError("a fitted blur of half-width " + std::to_string(halfWidth) +
                            " cells is outside the shader's 1.." +
                            std::to_string(glsl::EXPOSURE_BLUR_MAX_HALF_WIDTH) +
                            "; use the CPU path");
    return halfWidth;
}

/// Rows per invocation: strips of about 256 rows on CPU drivers, where each strip's lead (2
/// halfWidth rows blurred along x and not stored) is the overhead and two threads need few
/// invocations, of about 32 on GPUs, which need many; the grid's rows shared evenly among the
/// strips, in whole iterations of the shader's strip loop (a last strip mostly past the grid would
/// cost as much as a full one).
uint32_t stripRowsFor(const gpu::DeviceInfo& device, uint32_t ny) {
    const uint32_t longest = device.isHardware() ? 32 : 256;
    const uint32_t strips = (ny + longest - 1) / longest;
    return roundUp((ny + strips - 1) / strips, STEPS);
}

}  // namespace

bool ExposureEngine::GpuState::fits(int halfWidth) {
    return shaderTakes(halfWidth);
}

ExposureEngine::GpuState::GpuState(std::shared_ptr<gpu::Context> context_, int nx_, int ny_,
                                   const std::vector<float>& tapValues, float normX_, float normY_)
    : context(std::move(context_)),
      nx(uint32_t(nx_)),
      ny(uint32_t(ny_)),
      halfWidth(checkedHalfWidth(tapValues)),
      stripRows(stripRowsFor(context->info(), ny)),
      normX(normX_),
      normY(normY_),
      // Each row: the padding, the cells to whole groups, and the reach of the last window (its
      // taps past the half-width and the 8 floats it reads ahead). Rows: the lead above the grid,
      // the grid to whole strips.
      depositWidth(paddingOf(halfWidth) + roundUp(nx, GROUP_OUTPUTS) +
                   roundUp(uint32_t(halfWidth) + CHUNK, 4)),
      depositTop(leadOf(halfWidth) - uint32_t(halfWidth)),
      runningWidth(roundUp(nx, GROUP_OUTPUTS)),
      depositSum(size_t(nx) * ny, 0.0f),
      deposit(context, uint64_t(depositWidth) * (roundUp(ny, stripRows) + leadOf(halfWidth)) *
                           sizeof(float)),
      running(context, uint64_t(runningWidth) * roundUp(ny, stripRows) * sizeof(float)),
      taps(context, glsl::EXPOSURE_TAP_BLOCK * sizeof(float)),
      kernel(context, exposure_blur_spv, sizeof exposure_blur_spv,
             {gpu::Binding::UniformTexels4, gpu::Binding::Uniform, gpu::Binding::Storage},
             sizeof(glsl::ExposureBlurParams), {{0, uint32_t(halfWidth)}, {1, stripRows}},
             GROUP_OUTPUTS / 8) {
    // The padding is zero once for all: the host writes the grid's cells only. R needs no
    // clearing: the shader writes every one of its cells before it is read.
    deposit.fill(0u);
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
    const size_t width = nx, stride = depositWidth, padding = paddingOf(halfWidth),
                 top = depositTop;
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, ny, 16), [&](const tbb::blocked_range<size_t>& rows) {
            for (size_t j = rows.begin(); j < rows.end(); ++j) {
                float* s = sum + j * width;
                const float* dj = d + j * width;
                for (size_t i = 0; i < width; ++i)
                    s[i] = restart ? dj[i] : glsl::printThroughStep(dj[i], s[i], decay);
                if (padded)
                    std::memcpy(padded + (j + top) * stride + padding, s, width * sizeof(float));
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
                       (uint64_t(depositTop) * depositWidth + paddingOf(halfWidth)) * sizeof(float),
                       depositWidth * sizeof(float));
    return blurUploaded();
}

double ExposureEngine::GpuState::blurUploaded() {
    glsl::ExposureBlurParams params{};
    params.nx = nx;
    params.ny = ny;
    params.sourceWidth = depositWidth;
    params.targetWidth = runningWidth;
    params.scale = float(1.0 / (double(normX) * double(normY)));
    return 1e-3 * context->submit([&](gpu::Recorder& r) {
        r.dispatch(kernel, {&deposit, &taps, &running}, &params,
                   roundUp(nx, GROUP_OUTPUTS) / GROUP_OUTPUTS, roundUp(ny, stripRows) / stripRows);
    });
}

void ExposureEngine::GpuState::downloadRunning(SurfaceGrid& host) const {
    running.downloadRows(host.values.data(), nx * sizeof(float), ny, 0,
                         runningWidth * sizeof(float), nx * sizeof(float));
}

}  // namespace vpsim::exposure
