#pragma once
// Private: the shader path of the exposure engine. The print-through recursion is taken on the
// deposit, on the host: S_k = D_k + a S_(k-1) (printThroughStep, the CPU path's recursion on the
// blurred maps), and since the blur is linear, its blur is the running sum R_k = B_k + a R_(k-1).
// The host updates S in place in the zero-padded deposit's host mirror (gpu::Buffer::hostMirror:
// the buffer itself where the host addresses it, as on lavapipe, else its staging copy), and one
// submission per layer moves it to the device, runs exposure_blur.comp (both passes in one
// dispatch) and brings R back to its mirror, where the slices read it. The taps are uploaded once
// per engine.
#include <memory>
#include <vector>

#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/gpu/context.h"

namespace vpsim::exposure {

/// Rows per iteration of exposure_blur.comp's strip loop: its ring of 2 halfWidth + 1 rows where
/// the y pass gathers (EXPOSURE_BLUR_GATHER_MAX_HALF_WIDTH), else EXPOSURE_BLUR_STEPS.
uint32_t blurStripSteps(int halfWidth);

/// Rows per invocation of exposure_blur.comp (its params.stripRows) on a grid `columns` workgroups
/// across and ny rows down. On GPUs, strips of about 32 rows: they need many invocations. On a
/// CPU driver, whose threads each run whole workgroups (DeviceInfo::hostThreads), the strip count
/// that keeps the busiest thread least busy: each strip costs its rows plus its lead (2 halfWidth
/// rows blurred along x and not stored), and the workgroups (columns times strips) go to the
/// threads whole. (Strips of about 256 rows, as before, gave 5 strips down a 1030-row grid where
/// 2 cost 7% fewer steps on 2 threads.) Either way the rows are shared evenly among the strips,
/// in whole iterations of the shader's strip loop (blurStripSteps; a last strip mostly past the
/// grid would cost as much as a full one).
uint32_t blurStripRows(const gpu::DeviceInfo& device, uint32_t columns, uint32_t ny, int halfWidth);

/// Whether `device` runs exposure_blur.comp: it stores R as 64-bit words (float8_io.glsl), so it
/// needs shaderInt64.
inline bool blurShaderRunsOn(const gpu::DeviceInfo& device) {
    return device.int64;
}

struct ExposureEngine::GpuState {
    /// @param taps the blur's 2 halfWidth + 1 taps; normX, normY the passes' divisors
    /// @throw ResourceError when the blur is wider than the shader takes (fits)
    GpuState(std::shared_ptr<gpu::Context> context, int nx, int ny, const std::vector<float>& taps,
             float normX, float normY);
    /// Adds `deposit` to the running deposit, S = D + decay S (restart: S = D), and blurs S
    /// into the device's running sum R. Returns GPU seconds.
    double addLayer(const SurfaceGrid& deposit, float decay, bool restart);
    /// Whether the shader takes a blur of this half-width (EXPOSURE_BLUR_MAX_HALF_WIDTH).
    static bool fits(int halfWidth);
    /// Blurs `map` alone into the device's R, leaving the running deposit as it is. Returns GPU
    /// seconds.
    double blur(const SurfaceGrid& map);
    void downloadRunning(SurfaceGrid& running) const;
    /// R in host memory (until the next blur; rows runningWidth cells apart).
    const float* runningOnHost() const;

    std::shared_ptr<gpu::Context> context;
    uint32_t nx, ny;
    int halfWidth;
    uint32_t stripRows;  ///< rows per invocation of the shader (its params.stripRows)
    float normX, normY;
    uint32_t depositWidth;  ///< row length of the padded deposit
    uint32_t depositTop;    ///< zero rows above the deposit's first row
    uint32_t runningWidth;  ///< row length of R on the device (nx to whole groups)
    /// S, the running deposit, apart from the deposit's mirror: only after blur() wrote over S
    /// there mid-run (sumOnHost), sized then.
    std::vector<float> depositSum;
    bool sumOnHost = false;      ///< whether S is in depositSum rather than the deposit's mirror
    float* depositMirror;        ///< the padded deposit in host memory (gpu::Buffer::hostMirror)
    const float* runningMirror;  ///< R in host memory, rows runningWidth cells apart
    gpu::Buffer deposit, running, taps;
    std::shared_ptr<const gpu::Kernel> kernel;  ///< shared by the engines of a tiled run

private:
    /// Blurs what the deposit's mirror holds into R, and brings R to its mirror.
    double blurMirror();
    /// Grid row j of the deposit's mirror (past the padding).
    float* mirrorRow(size_t j);
    float* sumRow(size_t j) { return depositSum.data() + j * nx; }
};

}  // namespace vpsim::exposure
