#include "exposure/tabulated_gpu.h"

#include <algorithm>
#include <cstdlib>

#include "exposure/copy_rows.h"
#include "exposure/exposure_glsl.h"
#include "vpsim/core/error.h"
#include "vpsim/shaders/exposure_stencil_spv.h"

namespace vpsim::exposure {
namespace {

constexpr int GROUP_ROWS = glsl::STENCIL_GROUP_Y;  ///< output rows per workgroup: 1 each
/// Its outputs along x: STENCIL_GROUP_X invocations of STENCIL_OUTPUTS outputs.
constexpr int GROUP_COLUMNS = glsl::STENCIL_GROUP_X * glsl::STENCIL_OUTPUTS;

int roundUp(int n, int m) {
    return (n + m - 1) / m * m;
}

/// The stencils' common shape: per row dj + H (H the largest half-width) the largest |di| of any
/// stencil's taps in that row, -1 where none has one.
std::vector<int> commonShape(const std::vector<DepthStencil>& stencils) {
    int H = 0;
    for (const auto& st : stencils) H = std::max(H, st.halfWidth);
    std::vector<int> shape(size_t(2 * H + 1), -1);
    for (const auto& st : stencils)
        for (int dj = -st.halfWidth; dj <= st.halfWidth; ++dj) {
            int& row = shape[size_t(dj + H)];
            row = std::max(row, st.rowHalfWidth[size_t(dj + st.halfWidth)]);
        }
    return shape;
}

/// The shader's rows: stencil rows d = 0..H of the shape (row -d is the same), each walked in
/// stencilRowChunks of its half-width.
int shapeChunks(const std::vector<int>& shape) {
    const int H = int(shape.size() / 2);
    int chunks = 0;
    for (int d = 0; d <= H; ++d) chunks += glsl::stencilRowChunks(shape[size_t(H + d)]);
    return chunks;
}

/// A stencil's weights on the common shape, in the shader's order: per row d = 0..H, its taps on
/// the row's chunks of STENCIL_CHUNK from stencilRowFirst (zeros outside the stencil's support).
std::vector<float> weightsOnShape(const DepthStencil& st, const std::vector<int>& shape) {
    const int H = int(shape.size() / 2);
    std::vector<float> weights;
    for (int d = 0; d <= H; ++d) {
        const int hw = shape[size_t(H + d)], first = glsl::stencilRowFirst(hw);
        for (int k = 0; k < glsl::stencilRowChunks(hw) * glsl::STENCIL_CHUNK; ++k) {
            const int di = first + k;
            const bool inside = std::abs(di) <= st.halfWidth && d <= st.halfWidth;
            weights.push_back(inside ? st.at(di, d) : 0.0f);
        }
    }
    return weights;
}

/// exposure_stencil.comp's specialisation: the shape's half-width, chunks and rows d = 0..H, and
/// the stencils per invocation.
std::vector<gpu::SpecConstant> shaderConstants(const std::vector<int>& shape, int perInvocation) {
    const size_t H = shape.size() / 2;
    std::vector<gpu::SpecConstant> constants{{0, uint32_t(H)}, {1, uint32_t(shapeChunks(shape))}};
    for (size_t d = 0; d <= H; ++d) constants.push_back({uint32_t(2 + d), uint32_t(shape[H + d])});
    constants.push_back({35, uint32_t(perInvocation)});
    return constants;
}

/// The most chunks the shader's unrolled body may hold for several stencils per invocation (each
/// stencil's shape chunks, all stencils together): its compilation grows with them. On lavapipe
/// here, uncached, at 12 cells each side (52 chunks): pipeline creation and the first dispatch
/// (where LLVM compiles) 0.06 + 0.51 s for one stencil, 0.30 + 1.05 s for four, about what the
/// shader took before the fold; at 32 cells (about 230 chunks) two stencils took 1.7 + 3.4 s. So
/// several stencils per invocation stay within four at 12 cells.
constexpr int MAX_UNROLLED_CHUNKS = 256;

/// The most stencils whose weights on `shape` fit the device's shared memory and uniform range
/// together (0: not even one), at most STENCIL_MAX_PER_INVOCATION, and more than one only within
/// MAX_UNROLLED_CHUNKS.
int mostPerInvocation(const std::vector<int>& shape, const gpu::DeviceInfo& device) {
    const int chunks = shapeChunks(shape);
    const uint64_t bytes = uint64_t(chunks) * glsl::STENCIL_CHUNK * sizeof(float);
    int most = 0;
    while (most < glsl::STENCIL_MAX_PER_INVOCATION &&
           (most + 1) * bytes <= device.maxSharedMemoryBytes &&
           (most + 1) * bytes <= device.maxUniformBufferRange &&
           (most == 0 || (most + 1) * chunks <= MAX_UNROLLED_CHUNKS))
        ++most;
    return most;
}

/// Stencils per invocation for M stencils on `device`. On a CPU driver, the fewest window fetches
/// and multiply-adds, counted as ceil(M / K) groups each costing a window (about one stencil's
/// multiply-adds on lavapipe: the fetch calls took as many JIT samples as the arithmetic with one
/// stencil) plus K stencils; the group's stencils past M have zero weights and still cost their
/// multiply-adds. Measured against one stencil per invocation: `bench_pipeline --engines` (M = 11)
/// 15.2 -> 13.0-13.9 ns/voxel with four, `bench_exposure engines` (M = 23) 27.6 -> 22.5-23.2.
/// One on a GPU, where fetches are cheap against the arithmetic (not yet measured there).
int chooseStencilsPerInvocation(int M, int most, const gpu::DeviceInfo& device) {
    if (device.hostThreads == 0) return 1;
    int best = 1;
    double bestCost = 1e300;
    for (int k = 1; k <= most; ++k) {
        const double cost = double((M + k - 1) / k) * (k + 1);
        if (cost <= bestCost) {
            best = k;
            bestCost = cost;
        }
    }
    return best;
}

}  // namespace

bool TabulatedExposureEngine::GpuState::fits(const std::vector<DepthStencil>& stencils,
                                             const gpu::DeviceInfo& device) {
    const std::vector<int> shape = commonShape(stencils);
    return int(shape.size() / 2) <= glsl::STENCIL_MAX_HALF_WIDTH &&
           mostPerInvocation(shape, device) >= 1;
}

TabulatedExposureEngine::GpuState::GpuState(std::shared_ptr<gpu::Context> context_, int nx_,
                                            int ny_, const std::vector<DepthStencil>& stencils,
                                            int slots)
    : context(std::move(context_)),
      nx(uint32_t(nx_)),
      ny(uint32_t(ny_)),
      shape(commonShape(stencils)),
      padding(int(shape.size() / 2)),
      columnPadding(uint32_t(roundUp(padding, 4))),
      // A row's last chunk reads at most STENCIL_CHUNK floats past the row's widest tap.
      paddedWidth(columnPadding + uint32_t(roundUp(nx_, GROUP_COLUMNS) +
                                           roundUp(padding + glsl::STENCIL_CHUNK, 4))),
      groupsX(uint32_t(roundUp(nx_, GROUP_COLUMNS) / GROUP_COLUMNS)),
      groupsY(uint32_t(roundUp(ny_, GROUP_ROWS) / GROUP_ROWS)),
      sliceWidth(groupsX * GROUP_COLUMNS),
      perInvocation(chooseStencilsPerInvocation(
          int(stencils.size()), mostPerInvocation(shape, context->info()), context->info())),
      deposit(context,
              uint64_t(paddedWidth) * (roundUp(ny_, GROUP_ROWS) + 2 * padding) * sizeof(float)),
      kernel(context, exposure_stencil_spv, sizeof exposure_stencil_spv,
             {gpu::Binding::UniformTexels4, gpu::Binding::Uniform, gpu::Binding::Storage,
              gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
             sizeof(glsl::ExposureStencilParams), shaderConstants(shape, perInvocation), 8) {
    // Stencils perInvocation m .. m + perInvocation - 1 share a weights block, zeros past the last.
    const size_t stencilFloats = size_t(shapeChunks(shape)) * glsl::STENCIL_CHUNK;
    for (size_t first = 0; first < stencils.size(); first += size_t(perInvocation)) {
        std::vector<float> group;
        for (size_t m = first; m < std::min(stencils.size(), first + size_t(perInvocation)); ++m) {
            const std::vector<float> onShape = weightsOnShape(stencils[m], shape);
            group.insert(group.end(), onShape.begin(), onShape.end());
        }
        group.resize(size_t(perInvocation) * stencilFloats, 0.0f);
        weights.emplace_back(context, group.size() * sizeof(float));
        weights.back().upload(group);
    }
    deposit.fill(0u);  // the border stays zero: the host writes the grid's cells only
    depositMirror = static_cast<float*>(deposit.hostMirror());
    // Rows and columns of whole workgroups, so the shader stores whole vec4 with no bounds test.
    const uint64_t sliceBytes = uint64_t(sliceWidth) * groupsY * GROUP_ROWS * sizeof(float);
    for (int s = 0; s < slots; ++s) {
        slices.emplace_back(context, sliceBytes);
        slices.back().hostMirror();
    }
    // Only a group of several stencils can hold one without a slice.
    if (perInvocation > 1) scratch = std::make_unique<gpu::Buffer>(context, sliceBytes);
    clearSlots();
}

double TabulatedExposureEngine::GpuState::addLayer(const SurfaceGrid& hostDeposit,
                                                   const std::vector<RowExtent>& extents,
                                                   const std::vector<std::pair<int, int>>& targets,
                                                   const std::vector<int>& finished) {
    copyRows(depositMirror + size_t(padding) * paddedWidth + columnPadding, paddedWidth,
             hostDeposit.values.data(), nx, nx, ny);
    const std::vector<GroupRect> rects = reachedGroups(extents);
    return 1e-3 * context->submit([&](gpu::Recorder& r) {
        for (int slot : toClear) r.fill(slices[slot], 0u);
        if (!toClear.empty()) r.barrier();
        toClear.clear();
        r.toDevice(deposit);
        // Each group of stencils with a target is one dispatch per rectangle; a stencil of the
        // group without one (the part's first layers, or past the last stencil) adds to scratch.
        // The bindings past perInvocation are not used: they take the group's first slice.
        std::vector<int> slotOf(weights.size() * size_t(perInvocation), -1);
        for (const auto& [m, slot] : targets) slotOf[size_t(m)] = slot;
        glsl::ExposureStencilParams params{};
        params.nx = nx;
        params.ny = ny;
        params.paddedWidth = paddedWidth;
        params.padding = padding;
        params.columnPadding = columnPadding;
        params.sliceWidth = sliceWidth;
        for (size_t g = 0; g < weights.size(); ++g) {
            std::vector<const gpu::Buffer*> buffers{&deposit, &weights[g]};
            bool any = false;
            for (int t = 0; t < perInvocation; ++t) {
                const int slot = slotOf[g * perInvocation + size_t(t)];
                buffers.push_back(slot >= 0 ? &slices[size_t(slot)] : scratch.get());
                any = any || slot >= 0;
            }
            if (!any) continue;
            buffers.resize(2 + glsl::STENCIL_MAX_PER_INVOCATION, buffers[2]);
            for (const GroupRect& rect : rects) {
                params.groupX = int(rect.x);
                params.groupY = int(rect.y);
                r.dispatch(kernel, buffers, &params, rect.width, rect.height);
            }
        }
        for (int slot : finished) r.toHost(slices[slot]);
    });
}

std::vector<TabulatedExposureEngine::GpuState::GroupRect>
TabulatedExposureEngine::GpuState::reachedGroups(const std::vector<RowExtent>& extents) const {
    // Per workgroup row, the workgroup columns that deposit rows within `padding` of its rows
    // reach, in the columns within `padding` of their extents (gaps in a row included).
    std::vector<GroupRect> rects;
    for (uint32_t gy = 0; gy < groupsY; ++gy) {
        const int top = std::max(0, int(gy) * GROUP_ROWS - padding);
        const int bottom = std::min(int(ny) - 1, int(gy + 1) * GROUP_ROWS - 1 + padding);
        int left = int(groupsX), right = -1;
        for (int r = top; r <= bottom; ++r) {
            const RowExtent& e = extents[size_t(r)];
            if (e.first > e.last) continue;
            left = std::min(left, std::max(0, e.first - padding) / GROUP_COLUMNS);
            right = std::max(right, std::min(int(nx) - 1, e.last + padding) / GROUP_COLUMNS);
        }
        if (right < left) continue;
        // Consecutive reached rows share one rectangle, as wide as all of them.
        GroupRect* last = rects.empty() ? nullptr : &rects.back();
        if (last && last->y + last->height == gy) {
            const uint32_t x0 = std::min(last->x, uint32_t(left));
            const uint32_t x1 = std::max(last->x + last->width, uint32_t(right) + 1);
            *last = {x0, last->y, x1 - x0, last->height + 1};
        } else {
            rects.push_back({uint32_t(left), gy, uint32_t(right - left + 1), 1});
        }
    }
    return rects;
}

void TabulatedExposureEngine::GpuState::takeSlot(int slot, SurfaceGrid& out) {
    copyRows(out.values.data(), nx, static_cast<const float*>(slices[slot].hostMirror()),
             sliceWidth, nx, ny);
    toClear.push_back(slot);
}

void TabulatedExposureEngine::GpuState::clearSlots() {
    toClear.clear();
    for (int slot = 0; slot < int(slices.size()); ++slot) toClear.push_back(slot);
}

}  // namespace vpsim::exposure
