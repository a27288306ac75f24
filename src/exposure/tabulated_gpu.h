#pragma once
// Private: the shader path of the tabulated-kernel engine. Accumulator slices stay on the device;
// per source layer the deposit is uploaded once, zero-padded, with a flag per row saying whether
// it holds any deposit, and each (stencil, slice) pair is one dispatch
// (shaders/exposure_stencil.comp) in one submission, which also clears the slices taken since the
// last one (no submission of their own).
#include <memory>
#include <vector>

#include "vpsim/exposure/tabulated_engine.h"
#include "vpsim/gpu/context.h"

namespace vpsim::exposure {

struct TabulatedExposureEngine::GpuState {
    /// @throw ResourceError when a stencil exceeds a uniform block (64 KiB: half-width about 60)
    /// or the padded deposit exceeds the device's texel-buffer limit
    GpuState(std::shared_ptr<gpu::Context> context, int nx, int ny,
             const std::vector<DepthStencil>& stencils, int slots);
    /// Adds the deposit gathered by stencil m to slot t for every (m, t) in `targets`; GPU seconds.
    double addLayer(const SurfaceGrid& deposit, const std::vector<std::pair<int, int>>& targets);
    /// Downloads slot t into `out`; the next addLayer clears it on the device.
    void takeSlot(int slot, SurfaceGrid& out);
    /// Clears every slot (with the next addLayer): a new run starts.
    void clearSlots();

    std::shared_ptr<gpu::Context> context;
    uint32_t nx, ny;
    int padding;             ///< zero rows above and below the deposit: the largest half-width
    uint32_t columnPadding;  ///< zero cells left of each row: padding to a multiple of 4
    uint32_t paddedWidth;    ///< row length of the padded deposit, a multiple of 4
    std::vector<int> halfWidths;
    gpu::Buffer deposit;
    gpu::Buffer rowFlags;              ///< per padded deposit row: 1 when it holds any deposit
    std::vector<uint32_t> hostFlags;   ///< the same on the host, filled per layer
    std::vector<gpu::Buffer> weights;  ///< one uniform block per stencil: its rows in chunks of 8
    std::vector<gpu::Buffer> rows;     ///< per stencil: each row's chunks and first tap
    std::vector<gpu::Buffer> slices;
    std::vector<int> toClear;  ///< slots taken since the last addLayer
    gpu::Kernel kernel;
};

}  // namespace vpsim::exposure
