#pragma once
// Private: the shader path of the tabulated-kernel engine. Accumulator slices stay on the device;
// per source layer one submission moves the zero-padded deposit to the device (the host writes it
// in the buffer's host mirror, gpu::Buffer::hostMirror), clears the slices taken since the last
// one (or, where the layer's sums cover every workgroup, has its dispatch write them), dispatches
// each group of perInvocation stencils with their slices (shaders/exposure_stencil.comp) over the
// rectangles of workgroups that the deposit reaches, and brings the layer's finished slices back
// to their mirrors, where the host takes them. The pipeline is specialised to the stencils'
// common shape (per stencil row, the widest row of any stencil), so each stencil's weights are
// laid out on that shape, one per cell that the 8-fold symmetry leaves (rows dj = 0..H, taps
// di = 0..hw, or di = dj..hw where diagonal).
#include <memory>
#include <vector>

#include "exposure/row_extents.h"
#include "vpsim/exposure/tabulated_engine.h"
#include "vpsim/gpu/context.h"

namespace vpsim::exposure {

struct TabulatedExposureEngine::GpuState {
    /// Whether the shader takes these stencils on `device`: their common shape at most
    /// glsl::STENCIL_MAX_HALF_WIDTH cells each side, and its weights within the device's shared
    /// memory and uniform-block range.
    static bool fits(const std::vector<DepthStencil>& stencils, const gpu::DeviceInfo& device);
    /// @throw ResourceError when the padded deposit exceeds the device's texel-buffer limit (at
    /// the first dispatch)
    GpuState(std::shared_ptr<gpu::Context> context, int nx, int ny,
             const std::vector<DepthStencil>& stencils, int slots);
    /// Adds the deposit (its rows' extents given) gathered by stencil m to slot t for every
    /// (m, t) in `targets`, then brings the `finished` slots to the host; GPU seconds.
    double addLayer(const SurfaceGrid& deposit, const std::vector<RowExtent>& extents,
                    const std::vector<std::pair<int, int>>& targets,
                    const std::vector<int>& finished);
    /// Workgroups, first and counts, of one dispatch.
    struct GroupRect {
        uint32_t x, y, width, height;
    };
    /// The rectangles of workgroups whose outputs some deposit reaches: runs of consecutive
    /// workgroup rows, each as wide as the union of its rows' reached columns.
    std::vector<GroupRect> reachedGroups(const std::vector<RowExtent>& extents) const;
    /// Copies finished slot t from its host mirror into `out`; the next addLayer clears it on
    /// the device.
    void takeSlot(int slot, SurfaceGrid& out);
    /// Clears every slot (with the next addLayer): a new run starts.
    void clearSlots();

    std::shared_ptr<gpu::Context> context;
    uint32_t nx, ny;
    std::vector<int> shape;  ///< the common shape: per row dj + padding, its half-width or -1
    int padding;             ///< zero rows above and below the deposit: the shape's half-width
    uint32_t columnPadding;  ///< zero cells left of each row: padding to a multiple of 4
    uint32_t paddedWidth;    ///< row length of the padded deposit, a multiple of 4
    uint32_t groupsX, groupsY;
    uint32_t sliceWidth;  ///< row length of a device slice: whole workgroups, a multiple of 4
    /// Whether the shader adds the cells of tap (x, d) and (d, x) before multiplying (its
    /// DIAGONAL), or only those of (x, d) and (-x, d) (each row's taps x = 0..hw in the weights).
    bool diagonal;
    /// Stencils each invocation applies to a fetched window (the shader's STENCILS).
    int perInvocation;
    gpu::Buffer deposit;
    float* depositMirror;  ///< the padded deposit in host memory (gpu::Buffer::hostMirror)
    /// A slice that takes the sums of a group's stencils without a target, never read (only
    /// when perInvocation > 1).
    std::unique_ptr<gpu::Buffer> scratch;
    /// One uniform block per group of perInvocation stencils (m / perInvocation), on the
    /// common shape.
    std::vector<gpu::Buffer> weights;
    std::vector<gpu::Buffer> slices;
    std::vector<int> toClear;                   ///< slots taken since the last addLayer
    std::shared_ptr<const gpu::Kernel> kernel;  ///< shared by the engines of a tiled run
};

}  // namespace vpsim::exposure
