#include "exposure/exposure_gpu.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "exposure/copy_rows.h"
#include "exposure/exposure_glsl.h"
#include "vpsim/core/error.h"
#include "vpsim/shaders/exposure_blur_spv.h"

namespace vpsim::exposure {
namespace {

constexpr uint32_t GROUP_OUTPUTS = 64;  ///< cells along x per group of exposure_blur.comp: 8 x 8
constexpr uint32_t CHUNK = uint32_t(glsl::STENCIL_CHUNK);

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

}  // namespace

uint32_t blurStripSteps(int halfWidth) {
    return halfWidth <= glsl::EXPOSURE_BLUR_GATHER_MAX_HALF_WIDTH ? 2 * uint32_t(halfWidth) + 1
                                                                  : glsl::EXPOSURE_BLUR_STEPS;
}

uint32_t blurStripRows(const gpu::DeviceInfo& device, uint32_t columns, uint32_t ny,
                       int halfWidth) {
    const uint32_t steps = blurStripSteps(halfWidth);
    const auto rowsOf = [&](uint32_t strips) { return roundUp((ny + strips - 1) / strips, steps); };
    if (device.hostThreads == 0) return rowsOf((ny + 31) / 32);
    const uint64_t threads = device.hostThreads, lead = leadOf(halfWidth);
    uint32_t best = 1;
    uint64_t bestSteps = UINT64_MAX;
    for (uint32_t strips = 1; strips <= (ny + steps - 1) / steps; ++strips) {
        const uint64_t groups = uint64_t(columns) * strips;
        const uint64_t busiest = (groups + threads - 1) / threads * (rowsOf(strips) + lead);
        if (busiest < bestSteps) {
            best = strips;
            bestSteps = busiest;
        }
    }
    return rowsOf(best);
}

bool ExposureEngine::GpuState::fits(int halfWidth) {
    return shaderTakes(halfWidth);
}

ExposureEngine::GpuState::GpuState(std::shared_ptr<gpu::Context> context_, int nx_, int ny_,
                                   const std::vector<float>& tapValues, float normX_, float normY_)
    : context(std::move(context_)),
      nx(uint32_t(nx_)),
      ny(uint32_t(ny_)),
      halfWidth(checkedHalfWidth(tapValues)),
      stripRows(blurStripRows(context->info(), roundUp(nx, GROUP_OUTPUTS) / GROUP_OUTPUTS, ny,
                              halfWidth)),
      normX(normX_),
      normY(normY_),
      // Each row: the padding, the cells to whole groups, and the reach of the last window (its
      // taps past the half-width and the 8 floats it reads ahead). Rows: the lead above the grid,
      // the grid to whole strips.
      depositWidth(paddingOf(halfWidth) + roundUp(nx, GROUP_OUTPUTS) +
                   roundUp(uint32_t(halfWidth) + CHUNK, 4)),
      depositTop(leadOf(halfWidth) - uint32_t(halfWidth)),
      runningWidth(roundUp(nx, GROUP_OUTPUTS)),
      deposit(context, uint64_t(depositWidth) * (roundUp(ny, stripRows) + leadOf(halfWidth)) *
                           sizeof(float)),
      running(context, uint64_t(runningWidth) * roundUp(ny, stripRows) * sizeof(float)),
      taps(context, glsl::EXPOSURE_TAP_BLOCK * sizeof(float)),
      kernel(gpu::Kernel::shared(
          context, exposure_blur_spv, sizeof exposure_blur_spv,
          {gpu::Binding::UniformTexels4, gpu::Binding::Uniform, gpu::Binding::Storage},
          sizeof(glsl::ExposureBlurParams), {{0, uint32_t(halfWidth)}}, GROUP_OUTPUTS / 8)) {
    // The padding is zero once for all (the mirror starts as the buffer): the host writes the
    // grid's cells only. R needs no clearing: the shader writes every one of its cells before it
    // is read.
    deposit.fill(0u);
    depositMirror = static_cast<float*>(deposit.hostMirror());
    runningMirror = static_cast<const float*>(running.hostMirror());
    std::vector<float> block(glsl::EXPOSURE_TAP_BLOCK, 0.0f);
    const int padding = int(paddingOf(halfWidth));
    for (int o = -halfWidth; o <= halfWidth; ++o)
        block[size_t(o + padding)] = tapValues[size_t(o + halfWidth)];
    taps.upload(block);
}

float* ExposureEngine::GpuState::mirrorRow(size_t j) {
    return depositMirror + (j + depositTop) * depositWidth + paddingOf(halfWidth);
}

double ExposureEngine::GpuState::addLayer(const SurfaceGrid& hostDeposit, float decay,
                                          bool restart) {
    const float* d = hostDeposit.values.data();
    const size_t width = nx;
    // S is updated where it lies in the deposit's padded rows in host memory (one pass reading D
    // and S and writing S), unless a blur of a map alone wrote over it since (blur), which left S
    // in depositSum.
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, ny, 16), [&](const tbb::blocked_range<size_t>& rows) {
            for (size_t j = rows.begin(); j < rows.end(); ++j) {
                const float* dj = d + j * width;
                float* to = mirrorRow(j);
                const float* from = sumOnHost ? sumRow(j) : to;
                for (size_t i = 0; i < width; ++i)
                    to[i] = restart ? dj[i] : glsl::printThroughStep(dj[i], from[i], decay);
            }
        });
    sumOnHost = false;
    return blurMirror();
}

const float* ExposureEngine::GpuState::runningOnHost() const {
    return runningMirror;
}

double ExposureEngine::GpuState::blur(const SurfaceGrid& map) {
    // A run's S is kept on the host first: the map goes where it lies.
    if (!sumOnHost) {
        depositSum.resize(size_t(nx) * ny);
        copyRows(depositSum.data(), nx, mirrorRow(0), depositWidth, nx, ny);
        sumOnHost = true;
    }
    copyRows(mirrorRow(0), depositWidth, map.values.data(), nx, nx, ny);
    return blurMirror();
}

double ExposureEngine::GpuState::blurMirror() {
    glsl::ExposureBlurParams params{};
    params.nx = nx;
    params.ny = ny;
    params.sourceWidth = depositWidth;
    params.targetWidth = runningWidth;
    params.scale = float(1.0 / (double(normX) * double(normY)));
    params.stripRows = stripRows;
    // One submission: the deposit to the device (a discrete GPU's), the blur, R back.
    return 1e-3 * context->submit([&](gpu::Recorder& r) {
        r.toDevice(deposit);
        r.dispatch(*kernel, {&deposit, &taps, &running}, &params,
                   roundUp(nx, GROUP_OUTPUTS) / GROUP_OUTPUTS, roundUp(ny, stripRows) / stripRows);
        r.toHost(running);
    });
}

void ExposureEngine::GpuState::downloadRunning(SurfaceGrid& host) const {
    copyRows(host.values.data(), nx, runningMirror, runningWidth, nx, ny);
}

}  // namespace vpsim::exposure
