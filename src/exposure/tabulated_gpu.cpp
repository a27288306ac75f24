#include "exposure/tabulated_gpu.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "exposure/copy_rows.h"
#include "exposure/exposure_glsl.h"
#include "vpsim/core/error.h"
#include "vpsim/shaders/exposure_stencil_spv.h"

namespace vpsim::exposure {
namespace {

constexpr int GROUP_ROWS = glsl::STENCIL_GROUP_ROWS;        ///< output rows per workgroup
constexpr int GROUP_COLUMNS = glsl::STENCIL_GROUP_COLUMNS;  ///< its output columns

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
    // The shader pairs tap (x, d) with (d, x) (and its windows reach on that): stencils built by
    // buildStencils are symmetric under the swap, so is their union.
    for (int d = 0; d <= H; ++d)
        for (int x = 0; x <= H; ++x)
            if ((x <= shape[size_t(H + d)]) != (d <= shape[size_t(H + x)]))
                throw std::logic_error("commonShape: the stencils are not symmetric in di, dj");
    return shape;
}

/// Floats of every folded row's window at once (exposure_stencil.comp's DIAGONAL): STENCIL_OUTPUTS
/// and the widest row's reach, rounded up to whole vec4, on either side, per row d = 0..H.
int diagonalWindowFloats(const std::vector<int>& shape) {
    const int H = int(shape.size() / 2);
    return (H + 1) * (glsl::STENCIL_OUTPUTS + 2 * roundUp(H, 4));
}

/// The most floats of windows the shader keeps at once: pipeline creation and the first dispatch
/// (where LLVM compiles) on lavapipe, uncached, at 12 cells each side (520 floats) 2.4 s with four
/// stencils, at 17 (1008) 12 s with three, at 32 (2640) 30 s with one; one row at a time took
/// 3.5 s at 17 cells with two stencils, 8 s at 32 with one (all before the closed-form index,
/// diagonalTap).
constexpr int DIAGONAL_MAX_WINDOW_FLOATS = 640;

/// Whether the shader adds the cells (+-x, +-d) and (+-d, +-x) before multiplying (DIAGONAL): on
/// CPU drivers within DIAGONAL_MAX_WINDOW_FLOATS. Not on a GPU, where every folded row's window
/// at once (520 floats at 12 cells each side) would be an invocation's registers many times over.
bool useDiagonal(const std::vector<int>& shape, const gpu::DeviceInfo& device) {
    return device.hostThreads > 0 && diagonalWindowFloats(shape) <= DIAGONAL_MAX_WINDOW_FLOATS;
}

/// Where DIAGONAL, the index of weight (x, d), d <= x <= H, of a stencil: rows d = 0..H of taps
/// x = d..H, whether the shape has them or not (exposure_stencil.comp computes it the same way).
/// A closed form, not a count of the shape's taps so far: lavapipe's compiler carried that count
/// through every unrolled tap, and the pipeline took 3.1-3.6 s to make instead of 0.9.
int diagonalTap(int H, int d, int x) {
    return d * (H + 1) - d * (d - 1) / 2 + x - d;
}

/// Weights per stencil in the shader, in whole vec4: per stencil row d = 0..H of the shape, the
/// taps x = 0..hw(d), or where `diagonal` x = d..H (the others have the same weights).
int shapeVec4s(const std::vector<int>& shape, bool diagonal) {
    const int H = int(shape.size() / 2);
    if (diagonal) return (diagonalTap(H, H, H) + 1 + 3) / 4;
    int taps = 0;
    for (int d = 0; d <= H; ++d) taps += std::max(0, shape[size_t(H + d)] + 1);
    return (taps + 3) / 4;
}

/// A stencil's weights on the common shape, in the shader's order: per row d = 0..H, w(x, d) for
/// the row's taps of shapeVec4s (zeros outside the stencil's support), zero-padded to whole vec4.
std::vector<float> weightsOnShape(const DepthStencil& st, const std::vector<int>& shape,
                                  bool diagonal) {
    const int H = int(shape.size() / 2);
    std::vector<float> weights;
    if (diagonal) {
        weights.assign(size_t(shapeVec4s(shape, true)) * 4, 0.0f);
        for (int d = 0; d <= H; ++d)
            for (int x = d; x <= std::min(shape[size_t(H + d)], st.halfWidth); ++x)
                weights[size_t(diagonalTap(H, d, x))] = st.at(x, d);
        return weights;
    }
    for (int d = 0; d <= H; ++d)
        for (int x = 0; x <= shape[size_t(H + d)]; ++x) {
            const bool inside = x <= st.halfWidth && d <= st.halfWidth;
            weights.push_back(inside ? st.at(x, d) : 0.0f);
        }
    weights.resize(size_t(shapeVec4s(shape, diagonal)) * 4, 0.0f);
    return weights;
}

/// exposure_stencil.comp's specialisation: the shape's half-width, weights and rows d = 0..H, the
/// stencils per invocation and DIAGONAL.
std::vector<gpu::SpecConstant> shaderConstants(const std::vector<int>& shape, bool diagonal,
                                               int perInvocation) {
    const size_t H = shape.size() / 2;
    std::vector<gpu::SpecConstant> constants{{0, uint32_t(H)},
                                             {1, uint32_t(shapeVec4s(shape, diagonal))}};
    for (size_t d = 0; d <= H; ++d) constants.push_back({uint32_t(2 + d), uint32_t(shape[H + d])});
    constants.push_back({35, uint32_t(perInvocation)});
    constants.push_back({36, uint32_t(diagonal)});
    return constants;
}

/// The most weights (in vec4, all the group's stencils together) of several stencils per
/// invocation: the shader's unrolled body and its compilation grow with them. Uncached on lavapipe
/// here, before the closed-form DIAGONAL index (diagonalTap), pipeline creation and the first
/// dispatch: 1.8 + 0.6 s for four stencils at 12 cells each side (DIAGONAL, 17 vec4 each), 3.5 +
/// 0.9 s for six; 3.5 s for two at 17 cells (one row at a time, 64 vec4 each). With it, six
/// DIAGONAL stencils at 12 cells (23 vec4 each: the whole triangle) take 0.9 s (Mesa's cache
/// warm), so the limit admits them.
constexpr int MAX_UNROLLED_VEC4S = 144;

/// The most stencils whose weights on `shape` fit the device's shared memory and uniform range
/// together (0: not even one), at most STENCIL_MAX_PER_INVOCATION, and more than one only within
/// MAX_UNROLLED_VEC4S.
int mostPerInvocation(const std::vector<int>& shape, const gpu::DeviceInfo& device) {
    const int vec4s = shapeVec4s(shape, useDiagonal(shape, device));
    const uint64_t bytes = uint64_t(vec4s) * 4 * sizeof(float);
    int most = 0;
    while (most < glsl::STENCIL_MAX_PER_INVOCATION &&
           (most + 1) * bytes <= device.maxSharedMemoryBytes &&
           (most + 1) * bytes <= device.maxUniformBufferRange &&
           (most == 0 || (most + 1) * vec4s <= MAX_UNROLLED_VEC4S))
        ++most;
    return most;
}

/// Stencils per invocation for M stencils on `device`. On a CPU driver, the least work, counted
/// as ceil(M / K) groups each costing its windows (their fetches and the cells added before the
/// multiplies, shared by the group: about two stencils' multiply-adds on lavapipe) plus K
/// stencils; the group's stencils past M have zero weights and still cost their multiply-adds.
/// `bench_pipeline --engines` (M = 11, DIAGONAL) with K = 1, 2, 3, 4: 13.3-13.9, 9.6-9.7,
/// 7.7-8.0, 6.9-7.6 ns/voxel, which a window of 2.4 stencils fits; K = 6 (two groups, the model's
/// choice): 6.2-6.7. One on a GPU, where fetches are cheap against the arithmetic (not yet
/// measured there).
int chooseStencilsPerInvocation(int M, int most, const gpu::DeviceInfo& device) {
    if (device.hostThreads == 0) return 1;
    int best = 1;
    double bestCost = 1e300;
    for (int k = 1; k <= most; ++k) {
        const double cost = double((M + k - 1) / k) * (k + 2);
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
      // A window reaches the widest row's half-width, rounded up to whole vec4, on either side.
      paddedWidth(2 * columnPadding + uint32_t(roundUp(nx_, GROUP_COLUMNS))),
      groupsX(uint32_t(roundUp(nx_, GROUP_COLUMNS) / GROUP_COLUMNS)),
      groupsY(uint32_t(roundUp(ny_, GROUP_ROWS) / GROUP_ROWS)),
      sliceWidth(groupsX * GROUP_COLUMNS),
      diagonal(useDiagonal(shape, context->info())),
      perInvocation(chooseStencilsPerInvocation(
          int(stencils.size()), mostPerInvocation(shape, context->info()), context->info())),
      deposit(context,
              uint64_t(paddedWidth) * (roundUp(ny_, GROUP_ROWS) + 2 * padding) * sizeof(float)),
      kernel(
          gpu::Kernel::shared(context, exposure_stencil_spv, sizeof exposure_stencil_spv,
                              {gpu::Binding::UniformTexels4, gpu::Binding::Uniform,
                               gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                               gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                              sizeof(glsl::ExposureStencilParams),
                              shaderConstants(shape, diagonal, perInvocation), 8)) {
    // Stencils perInvocation m .. m + perInvocation - 1 share a weights block, zeros past the last.
    for (size_t first = 0; first < stencils.size(); first += size_t(perInvocation)) {
        std::vector<float> group;
        for (size_t m = first; m < std::min(stencils.size(), first + size_t(perInvocation)); ++m) {
            const std::vector<float> onShape = weightsOnShape(stencils[m], shape, diagonal);
            group.insert(group.end(), onShape.begin(), onShape.end());
        }
        group.resize(size_t(perInvocation) * size_t(shapeVec4s(shape, diagonal)) * 4, 0.0f);
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
    std::vector<int> slotOf(weights.size() * size_t(perInvocation), -1);
    for (const auto& [m, slot] : targets) slotOf[size_t(m)] = slot;
    // A slot to clear whose first sums cover every workgroup (one dispatch, a slot being the
    // target of one stencil) is written by it instead: no clear, and no load of the zeros.
    std::vector<char> written(slices.size(), 0);
    const bool whole = rects.size() == 1 && rects[0].width == groupsX && rects[0].height == groupsY;
    if (whole)
        for (int slot : toClear)
            written[size_t(slot)] = std::find(slotOf.begin(), slotOf.end(), slot) != slotOf.end();
    return 1e-3 * context->submit([&](gpu::Recorder& r) {
        bool cleared = false;
        for (int slot : toClear)
            if (!written[size_t(slot)]) {
                r.fill(slices[slot], 0u);
                cleared = true;
            }
        if (cleared) r.barrier();
        toClear.clear();
        r.toDevice(deposit);
        // Each group of stencils with a target is one dispatch per rectangle; a stencil of the
        // group without one (the part's first layers, or past the last stencil) adds to scratch.
        // The bindings past perInvocation are not used: they take the group's first slice.
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
            params.storeMask = 0;
            for (int t = 0; t < perInvocation; ++t) {
                const int slot = slotOf[g * perInvocation + size_t(t)];
                buffers.push_back(slot >= 0 ? &slices[size_t(slot)] : scratch.get());
                any = any || slot >= 0;
                if (slot >= 0 && written[size_t(slot)]) params.storeMask |= 1u << t;
            }
            if (!any) continue;
            buffers.resize(2 + glsl::STENCIL_MAX_PER_INVOCATION, buffers[2]);
            for (const GroupRect& rect : rects) {
                params.groupX = int(rect.x);
                params.groupY = int(rect.y);
                r.dispatch(*kernel, buffers, &params, rect.width, rect.height);
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
