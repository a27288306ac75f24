#pragma once
// Private: the shader path of the tabulated-kernel engine. Accumulator slices stay on the device;
// per source layer the deposit is uploaded once and each (stencil, slice) pair is one dispatch.
#include <memory>
#include <vector>

#include "vpsim/exposure/tabulated_engine.h"
#include "vpsim/gpu/context.h"

namespace vpsim::exposure {

struct TabulatedExposureEngine::GpuState {
    GpuState(std::shared_ptr<gpu::Context> context, int nx, int ny,
             const std::vector<DepthStencil>& stencils, int slots);
    /// Adds the deposit gathered by stencil m to slot t for every (m, t) in `targets`; GPU seconds.
    double addLayer(const SurfaceGrid& deposit, const std::vector<std::pair<int, int>>& targets);
    /// Downloads slot t into `out` and clears it on the device.
    void takeSlot(int slot, SurfaceGrid& out);

    std::shared_ptr<gpu::Context> context;
    uint32_t nx, ny;
    std::vector<int> halfWidths;
    std::vector<uint32_t> offsets;
    gpu::Buffer deposit, weights;
    std::vector<gpu::Buffer> slices;
    gpu::Kernel kernel;
};

}  // namespace vpsim::exposure
