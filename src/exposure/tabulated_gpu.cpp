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

/// exposure_stencil.comp's specialisation: the shape's half-width, chunks and rows.
std::vector<gpu::SpecConstant> shapeConstants(const std::vector<int>& shape) {
    std::vector<gpu::SpecConstant> constants{{0, uint32_t(shape.size() / 2)},
                                             {1, uint32_t(shapeChunks(shape))}};
    for (size_t t = 0; t < shape.size(); ++t)
        constants.push_back({uint32_t(2 + t), uint32_t(shape[t])});
    return constants;
}

}  // namespace

bool TabulatedExposureEngine::GpuState::fits(const std::vector<DepthStencil>& stencils,
                                             const gpu::DeviceInfo& device) {
    const std::vector<int> shape = commonShape(stencils);
    const uint64_t bytes = uint64_t(shapeChunks(shape)) * glsl::STENCIL_CHUNK * sizeof(float);
    return int(shape.size() / 2) <= glsl::STENCIL_MAX_HALF_WIDTH &&
           bytes <= device.maxSharedMemoryBytes && bytes <= device.maxUniformBufferRange;
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
      deposit(context,
              uint64_t(paddedWidth) * (roundUp(ny_, GROUP_ROWS) + 2 * padding) * sizeof(float)),
      kernel(context, exposure_stencil_spv, sizeof exposure_stencil_spv,
             {gpu::Binding::UniformTexels4, gpu::Binding::Uniform, gpu::Binding::Storage},
             sizeof(glsl::ExposureStencilParams), shapeConstants(shape), 8) {
    for (const auto& st : stencils) {
        const std::vector<float> onShape = weightsOnShape(st, shape);
        weights.emplace_back(context, onShape.size() * sizeof(float));
        weights.back().upload(onShape);
    }
    deposit.fill(0u);  // the border stays zero: the host writes the grid's cells only
    depositMirror = static_cast<float*>(deposit.hostMirror());
    // Rows and columns of whole workgroups, so the shader stores whole vec4 with no bounds test.
    const uint64_t sliceBytes = uint64_t(sliceWidth) * groupsY * GROUP_ROWS * sizeof(float);
    for (int s = 0; s < slots; ++s) {
        slices.emplace_back(context, sliceBytes);
        slices.back().hostMirror();
    }
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
        for (const auto& [m, slot] : targets) {
            glsl::ExposureStencilParams params{};
            params.nx = nx;
            params.ny = ny;
            params.paddedWidth = paddedWidth;
            params.padding = padding;
            params.columnPadding = columnPadding;
            params.sliceWidth = sliceWidth;
            for (const GroupRect& rect : rects) {
                params.groupX = int(rect.x);
                params.groupY = int(rect.y);
                r.dispatch(kernel, {&deposit, &weights[m], &slices[slot]}, &params, rect.width,
                           rect.height);
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
