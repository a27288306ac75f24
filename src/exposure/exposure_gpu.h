#pragma once
// Private: the shader path of the exposure engine. The deposit is uploaded once per layer into a
// zero-padded texel buffer, the two blur passes (the x pass writes its result transposed, so the y
// pass also runs along rows) and the print-through step are two dispatches in
// one submission, and the running sum R stays on the device (downloaded once per layer for the
// slices); the taps are uploaded once per engine.
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
    /// Blurs `deposit` and updates the device's running sum R = B + decay R (restart: R = B).
    /// Returns GPU seconds.
    double addLayer(const SurfaceGrid& deposit, float decay, bool restart);
    /// Uploads `running` as the device's running sum.
    void setRunning(const SurfaceGrid& running);
    void downloadRunning(SurfaceGrid& running) const;

    std::shared_ptr<gpu::Context> context;
    uint32_t nx, ny;
    int halfWidth;
    float normX, normY;
    uint32_t depositWidth;  ///< row length of the padded deposit (the x pass's source)
    uint32_t passWidth;     ///< row length of the transposed pass buffer (the y pass's source)
    gpu::Buffer deposit, pass, running, taps;
    gpu::Kernel alongX, alongY;
};

}  // namespace vpsim::exposure
