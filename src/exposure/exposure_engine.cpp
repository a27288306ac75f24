#include "vpsim/exposure/exposure_engine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "exposure/avx2_clones.h"
#include "exposure/exposure_glsl.h"
#include "exposure/exposure_gpu.h"
#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/text.h"
#include "vpsim/exposure/deposit.h"

namespace vpsim::exposure {
namespace {

/// The blur's taps -halfWidth..halfWidth, shared by the CPU passes and the shaders' uniform block.
std::vector<float> blurTaps(int halfWidth, float sigmaCells) {
    std::vector<float> taps(2 * halfWidth + 1);
    for (int o = -halfWidth; o <= halfWidth; ++o)
        taps[o + halfWidth] = glsl::gaussianTap(o, sigmaCells);
    return taps;
}

/// sum[i] += tap * in[i] over [first, last): a tap at a time, for the cells outside sumTaps'
/// blocks (also built for AVX2; without FMA, so nothing is contracted).
VPSIM_AVX2_CLONES void addTap(float* __restrict sum, const float* __restrict in, float tap,
                              int first, int last) {
    for (int i = first; i < last; ++i) sum[i] += tap * in[i];
}

/// sum[i] = taps[0] * in[at + i] + taps[1] * in[at + step + i] + ... (added in that order, from
/// 0) for i in [first, last): the blur's inner loop. Blocks of cells are summed over every tap in
/// registers before they are stored (instead of a pass over the row per tap, which loads and
/// stores the sums once per tap); each cell's sum is the same, term for term. Built for AVX2
/// too (chosen at run time where the processor has it): AVX2 alone has no FMA, so nothing is
/// contracted and every sum is bit for bit the baseline's.
VPSIM_AVX2_CLONES void sumTaps(float* __restrict sum, const float* __restrict in, ptrdiff_t at,
                               ptrdiff_t step, const float* taps, int count, int first, int last) {
    constexpr int BLOCK = 64;  // eight AVX2 registers: eight sums in flight per tap
    int i = first;
    for (; i + BLOCK <= last; i += BLOCK) {
        float block[BLOCK] = {};
        for (int t = 0; t < count; ++t) {
            const float tap = taps[t];
            const float* cells = in + (at + t * step + i);
            for (int k = 0; k < BLOCK; ++k) block[k] += tap * cells[k];
        }
        for (int k = 0; k < BLOCK; ++k) sum[i + k] = block[k];
    }
    std::fill(sum + i, sum + last, 0.0f);
    for (int t = 0; t < count; ++t) addTap(sum, in + (at + t * step), taps[t], i, last);
}

/// One 1D Gaussian pass on the CPU: the same sums as shaders/exposure_blur.comp.
void blurPassCpu(const SurfaceGrid& source, SurfaceGrid& target, int axis, int halfWidth,
                 float sigmaCells, float norm) {
    const int nx = source.nx, ny = source.ny;
    const std::vector<float> taps = blurTaps(halfWidth, sigmaCells);
    // Each cell sums its taps in the order o = lo..hi, as the shader does; taps beyond the grid
    // are left out (not added as zeros), as the shader leaves them out.
    tbb::parallel_for(tbb::blocked_range<int>(0, ny, 4), [&](const tbb::blocked_range<int>& rows) {
        std::vector<float> sum(nx);
        for (int j = rows.begin(); j < rows.end(); ++j) {
            const float* row = &source.values[size_t(j) * nx];
            float* out = &target.values[size_t(j) * nx];
            if (axis == 0) {
                // The cells with every tap inside the row, then those near its ends a tap at a
                // time.
                const int inner0 = std::min(halfWidth, nx),
                          inner1 = std::max(inner0, nx - halfWidth);
                sumTaps(sum.data(), row, -halfWidth, 1, taps.data(), 2 * halfWidth + 1, inner0,
                        inner1);
                std::fill(sum.begin(), sum.begin() + inner0, 0.0f);
                std::fill(sum.begin() + inner1, sum.end(), 0.0f);
                for (int o = -halfWidth; o <= halfWidth; ++o) {
                    const float tap = taps[o + halfWidth];
                    addTap(sum.data(), row + o, tap, std::max(0, -o), std::min(inner0, nx - o));
                    addTap(sum.data(), row + o, tap, std::max(inner1, -o), std::min(nx, nx - o));
                }
            } else {
                const int lo = std::max(-halfWidth, -j), hi = std::min(halfWidth, ny - 1 - j);
                sumTaps(sum.data(), row, ptrdiff_t(lo) * nx, nx, &taps[lo + halfWidth], hi - lo + 1,
                        0, nx);
            }
            for (int i = 0; i < nx; ++i) out[i] = sum[i] / norm;
        }
    });
}

}  // namespace

int blurHalfWidth(double radius, double pitch) {
    return int(std::ceil(1.75 * radius / pitch));
}

ExposureEngine::ExposureEngine(const ExposureGrid& grid, const kernel::FittedBeam& beam,
                               double layerThickness, std::shared_ptr<gpu::Context> context)
    : mGrid(grid), mBeam(beam), mLayerThickness(layerThickness) {
    if (grid.nx <= 0 || grid.ny <= 0) throw InputError("exposure grid has no cells");
    if (!(grid.pitch > 0)) throw InputError("exposure grid pitch must be positive");
    if (grid.slicesPerLayer < 1) throw InputError("at least one voxel slice per layer is needed");
    if (!(beam.radius > 0)) throw InputError("beam radius (We3D) must be positive");
    if (!(beam.attenuationLength > 0))
        throw InputError("attenuation length (De3D) must be positive");
    if (!(beam.efficiency > 0)) throw InputError("beam efficiency must be positive");
    if (!(layerThickness > 0)) throw InputError("layer thickness must be positive");
    if (beam.radius < grid.pitch)
        throw InputError("grid pitch " + formatQuantity(grid.pitch * 1e3) +
                         " um is coarser than the beam radius " +
                         formatQuantity(beam.radius * 1e3) +
                         " um: the blur would be meaningless; refine the grid");
    const double cells = double(grid.nx) * grid.ny;
    const double bytes = cells * sizeof(float) * 4;  // deposit, two blur buffers, running sum
    if (cells > 4.0e8 || bytes > 8.0 * (1ull << 30))
        throw ResourceError("exposure grid of " + std::to_string(grid.nx) + " x " +
                            std::to_string(grid.ny) + " cells needs " + formatBytes(bytes) +
                            " of working memory per layer; use a coarser pitch");
    const Blur blur = blurOf();
    if (context && !GpuState::fits(blur.halfWidth)) {
        // Once per process: a tiled run makes an engine per tile.
        static std::once_flag warned;
        std::call_once(warned, [&] {
            logWarn("a fitted blur " + std::to_string(blur.halfWidth) +
                    " cells wide each side is wider than the exposure shader takes (" +
                    std::to_string(glsl::EXPOSURE_BLUR_MAX_HALF_WIDTH) +
                    "); exposing on the CPU path");
        });
    } else if (context && !blurShaderRunsOn(context->info())) {
        static std::once_flag warned;
        std::call_once(warned, [&] {
            logWarn("device '" + context->info().name +
                    "' lacks shaderInt64, with which the fitted exposure shader stores its "
                    "results; exposing on the CPU path");
        });
    } else if (context) {
        mGpu = std::make_unique<GpuState>(context, grid.nx, grid.ny,
                                          blurTaps(blur.halfWidth, blur.sigmaCells), blur.normX,
                                          blur.normY);
    }
}

ExposureEngine::Blur ExposureEngine::blurOf() const {
    Blur blur;
    blur.sigmaCells = float(0.5 * mBeam.radius / mGrid.pitch);
    blur.halfWidth = blurHalfWidth(mBeam.radius, mGrid.pitch);
    // The efficiency scales the second pass's normalisation, so it costs nothing per tap.
    blur.normX = glsl::gaussianNorm(blur.halfWidth, blur.sigmaCells);
    blur.normY = float(blur.normX / mBeam.efficiency);
    return blur;
}

ExposureEngine::~ExposureEngine() = default;

void ExposureEngine::blurAndAccumulateCpu(SurfaceGrid& deposit, SurfaceGrid& running, float decay,
                                          double& seconds, SurfaceGrid& pass) {
    const Blur b = blurOf();
    auto start = std::chrono::steady_clock::now();
    // Every cell of `pass` is written by the first pass: a reused buffer needs no clearing.
    if (pass.nx != deposit.nx || pass.ny != deposit.ny)
        pass = SurfaceGrid(deposit.nx, deposit.ny, deposit.originX, deposit.originY, deposit.pitch);
    blurPassCpu(deposit, pass, 0, b.halfWidth, b.sigmaCells, b.normX);
    blurPassCpu(pass, deposit, 1, b.halfWidth, b.sigmaCells, b.normY);
    float* sum = running.values.data();
    const float* blurred = deposit.values.data();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, running.values.size(), 1 << 16),
                      [&](const tbb::blocked_range<size_t>& cells) {
                          for (size_t c = cells.begin(); c < cells.end(); ++c)
                              sum[c] = glsl::printThroughStep(blurred[c], sum[c], decay);
                      });
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

SurfaceGrid ExposureEngine::layerMap(const SurfaceGrid& deposit, double depth) {
    SurfaceGrid running = mGrid.surface();
    if (mGpu) {
        // Leaves a run's running deposit as it is (GpuState::blur keeps it). A run's R read in
        // place is kept first: this blur writes over R.
        if (mRunningView && mRunningView != mRunning.values.data()) {
            mGpu->downloadRunning(mRunning);
            mRunningView = mRunning.values.data();
            mRunningStride = size_t(mGrid.nx);
        }
        mGpu->blur(deposit);
        mGpu->downloadRunning(running);
    } else {
        SurfaceGrid blurred = deposit, pass;
        double seconds = 0;
        blurAndAccumulateCpu(blurred, running, 0.0f, seconds, pass);
    }
    const float attenuation = float(std::exp(-depth / mBeam.attenuationLength));
    for (float& v : running.values) v *= attenuation;
    return running;
}

SurfaceGrid ExposureEngine::layerMapAdjoint(const SurfaceGrid& map, double depth) {
    return layerMap(map, depth);
}

void ExposureEngine::beginLayers(int layers) {
    mRunning = mGrid.surface();
    mSlice = mGrid.surface();
    mGpuRestart = true;
}

double ExposureEngine::addLayer(int k, SurfaceGrid& deposit) {
    const float decay = float(std::exp(-mLayerThickness / mBeam.attenuationLength));
    double seconds = 0;
    mRunningView = mRunning.values.data();
    mRunningStride = size_t(mGrid.nx);
    if (!mGpu) {
        blurAndAccumulateCpu(deposit, mRunning, decay, seconds, mPass);
        return seconds;
    }
    seconds = mGpu->addLayer(deposit, decay, mGpuRestart);
    mGpuRestart = false;
    mRunningView = mGpu->runningOnHost();  // the slices read R where it lies
    mRunningStride = mGpu->runningWidth;
    return seconds;
}

void ExposureEngine::emitLayer(int k, double top, const SliceSink& sink) {
    const double voxelHeight = mLayerThickness / mGrid.slicesPerLayer;
    for (int s = 0; s < mGrid.slicesPerLayer; ++s) {
        double depth = (s + 0.5) * voxelHeight;
        float attenuation = float(std::exp(-depth / mBeam.attenuationLength));
        const float* running = mRunningView;
        float* slice = mSlice.values.data();
        const size_t nx = size_t(mGrid.nx), stride = mRunningStride;
        const size_t rowsPerTask = std::max<size_t>(1, (size_t(1) << 16) / nx);
        tbb::parallel_for(tbb::blocked_range<size_t>(0, size_t(mGrid.ny), rowsPerTask),
                          [&](const tbb::blocked_range<size_t>& rows) {
                              for (size_t j = rows.begin(); j < rows.end(); ++j) {
                                  const float* from = running + j * stride;
                                  float* to = slice + j * nx;
                                  for (size_t i = 0; i < nx; ++i) to[i] = attenuation * from[i];
                              }
                          });
        sink({k, s, top - depth, &mSlice});
    }
}

std::vector<SurfaceGrid> ExposureEngine::stackAdjoint(const ExposureField& field) {
    const int n = mGrid.slicesPerLayer;
    const int layers = fieldLayers(field, mGrid);
    const double voxelHeight = mLayerThickness / n;
    const double decay = std::exp(-mLayerThickness / mBeam.attenuationLength);
    std::vector<double> weights(n);
    for (int s = 0; s < n; ++s)
        weights[s] = std::exp(-(s + 0.5) * voxelHeight / mBeam.attenuationLength);
    std::vector<SurfaceGrid> deposits;
    SurfaceGrid running = mGrid.surface();  // V_j, from the bottom up
    for (int k = 0; k < layers; ++k) {
        tbb::parallel_for(size_t(0), running.values.size(), [&](size_t c) {
            double sum = decay * running.values[c];
            for (int s = 0; s < n; ++s) sum += weights[s] * field[size_t(k) * n + s].values[c];
            running.values[c] = float(sum);
        });
        deposits.push_back(layerMap(running, 0.0));
    }
    return deposits;
}

}  // namespace vpsim::exposure
