#pragma once
// Private: the shader path of the exposure engine. The print-through recursion is taken on the
// deposit, on the host: S_k = D_k + a S_(k-1) (printThroughStep, the CPU path's recursion on the
// blurred maps), and since the blur is linear, its blur is the running sum R_k = B_k + a R_(k-1).
// S is uploaded once per layer into a zero-padded texel buffer; the two blur passes (the x pass
// writes its result transposed, so the y pass also runs along rows) are two dispatches in one
// submission, the y pass storing R (downloaded once per layer for the slices, or read where it
// lies when the host addresses the device's memory, as on lavapipe). The taps are uploaded once
// per engine.
#include <memory>
#include <vector>

#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/gpu/context.h"

namespace vpsim::exposure {

struct ExposureEngine::GpuState {
    /// @param taps the blur's 2 halfWidth + 1 taps; normX, normY the passes' divisors
    /// @throw ResourceError when the taps exceed the shader's block (EXPOSURE_TAP_BLOCK)
    GpuState(std::shared_ptr<gpu::Context> context, int nx, int ny, const std::vector<float>& taps,
             float normX, float normY);
    /// Adds `deposit` to the running deposit, S = D + decay S (restart: S = D), and blurs S
    /// into the device's running sum R. Returns GPU seconds.
    double addLayer(const SurfaceGrid& deposit, float decay, bool restart);
    /// Blurs `map` alone into the device's R, leaving the running deposit as it is. Returns GPU
    /// seconds.
    double blur(const SurfaceGrid& map);
    void downloadRunning(SurfaceGrid& running) const;
    /// R where the host addresses the device's buffer (until the next blur), else nullptr.
    const float* runningOnHost() const;

    std::shared_ptr<gpu::Context> context;
    uint32_t nx, ny;
    int halfWidth;
    float normX, normY;
    uint32_t depositWidth;  ///< row length of the padded deposit (the x pass's source)
    uint32_t passWidth;     ///< row length of the transposed pass buffer (the y pass's source)
    std::vector<float> depositSum;  ///< S, the running deposit, on the host
    gpu::Buffer deposit, pass, running, taps;
    gpu::Kernel alongX, alongY;

private:
    /// Uploads nx x ny floats and runs both passes into R.
    double blurRows(const float* source);
    /// Runs both passes on what the deposit buffer holds.
    double blurUploaded();
};

}  // namespace vpsim::exposure
