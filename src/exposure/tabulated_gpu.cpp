#include "exposure/tabulated_gpu.h"

#include <algorithm>
#include <cstdlib>

#include "exposure/exposure_glsl.h"
#include "vpsim/core/error.h"
#include "vpsim/shaders/exposure_stencil_spv.h"

namespace vpsim::exposure {
namespace {

constexpr int GROUP_ROWS = 8;      ///< local_size_y of exposure_stencil.comp: output rows per group
constexpr int GROUP_COLUMNS = 64;  ///< its outputs per group along x: 8 invocations of 8 outputs
constexpr int WINDOW_REACH = 16;   ///< floats a chunk's window reads past its first tap's

int roundUp(int n, int m) {
    return (n + m - 1) / m * m;
}

/// A stencil laid out for the shader: each row's taps in chunks of STENCIL_CHUNK from a first tap
/// aligned to 4 cells (zeros outside the row's support), and per row its (first chunk, chunk
/// count, first tap's di, 0).
struct ChunkedStencil {
    std::vector<float> weights;
    std::vector<int32_t> rows;
};

ChunkedStencil chunkedStencil(const DepthStencil& st) {
    const int H = st.halfWidth, chunk = glsl::STENCIL_CHUNK;
    ChunkedStencil out;
    out.rows.assign(4 * size_t(glsl::STENCIL_ROW_BLOCK), 0);
    int chunks = 0;
    for (int dj = -H; dj <= H; ++dj) {
        const int hw = st.rowHalfWidth[size_t(dj + H)];
        const int first = -roundUp(std::max(hw, 0), 4);
        const int count = hw < 0 ? 0 : (hw - first + chunk) / chunk;
        int32_t* row = &out.rows[4 * size_t(dj + H)];
        row[0] = chunks;
        row[1] = count;
        row[2] = first;
        for (int k = 0; k < count * chunk; ++k) {
            const int di = first + k;
            out.weights.push_back(std::abs(di) <= H ? st.at(di, dj) : 0.0f);
        }
        chunks += count;
    }
    if (chunks > glsl::STENCIL_CHUNK_BLOCK || 2 * H + 1 > glsl::STENCIL_ROW_BLOCK)
        throw ResourceError("a tabulated stencil of half-width " + std::to_string(H) +
                            " cells exceeds the shader's 64 KiB weight block; use a coarser pitch "
                            "or the CPU path");
    out.weights.resize(size_t(glsl::STENCIL_CHUNK_BLOCK) * chunk, 0.0f);
    return out;
}

int largestHalfWidth(const std::vector<DepthStencil>& stencils) {
    int H = 0;
    for (const auto& st : stencils) H = std::max(H, st.halfWidth);
    return H;
}

}  // namespace

TabulatedExposureEngine::GpuState::GpuState(std::shared_ptr<gpu::Context> context_, int nx_,
                                            int ny_, const std::vector<DepthStencil>& stencils,
                                            int slots)
    : context(std::move(context_)),
      nx(uint32_t(nx_)),
      ny(uint32_t(ny_)),
      padding(largestHalfWidth(stencils)),
      columnPadding(uint32_t(roundUp(padding, 4))),
      paddedWidth(columnPadding +
                  uint32_t(roundUp(nx_, GROUP_COLUMNS) + roundUp(padding + WINDOW_REACH, 4))),
      deposit(context,
              uint64_t(paddedWidth) * (roundUp(ny_, GROUP_ROWS) + 2 * padding) * sizeof(float)),
      rowFlags(context, uint64_t(roundUp(ny_, GROUP_ROWS) + 2 * padding) * sizeof(uint32_t)),
      hostFlags(size_t(roundUp(ny_, GROUP_ROWS) + 2 * padding), 0u),
      kernel(context, exposure_stencil_spv, sizeof exposure_stencil_spv,
             {gpu::Binding::UniformTexels4, gpu::Binding::Uniform, gpu::Binding::Uniform,
              gpu::Binding::Storage, gpu::Binding::Storage},
             sizeof(glsl::ExposureStencilParams), {}, GROUP_COLUMNS / 8) {
    for (const auto& st : stencils) {
        const ChunkedStencil chunked = chunkedStencil(st);
        halfWidths.push_back(st.halfWidth);
        weights.emplace_back(context, chunked.weights.size() * sizeof(float));
        weights.back().upload(chunked.weights);
        rows.emplace_back(context, chunked.rows.size() * sizeof(int32_t));
        rows.back().upload(chunked.rows);
    }
    deposit.fill(0u);  // the border stays zero: uploads write the grid's cells only
    rowFlags.fill(0u);
    for (int s = 0; s < slots; ++s) slices.emplace_back(context, uint64_t(nx) * ny * sizeof(float));
    clearSlots();
}

double TabulatedExposureEngine::GpuState::addLayer(
    const SurfaceGrid& hostDeposit, const std::vector<std::pair<int, int>>& targets) {
    deposit.uploadRows(hostDeposit.values.data(), nx * sizeof(float), ny, nx * sizeof(float),
                       (uint64_t(padding) * paddedWidth + columnPadding) * sizeof(float),
                       paddedWidth * sizeof(float));
    for (uint32_t j = 0; j < ny; ++j) {
        const float* row = hostDeposit.values.data() + size_t(j) * nx;
        hostFlags[size_t(padding) + j] =
            std::any_of(row, row + nx, [](float v) { return v != 0.0f; }) ? 1u : 0u;
    }
    rowFlags.upload(hostFlags);
    const uint32_t groupsX = uint32_t(roundUp(int(nx), GROUP_COLUMNS) / GROUP_COLUMNS);
    const uint32_t groupsY = uint32_t(roundUp(int(ny), GROUP_ROWS) / GROUP_ROWS);
    return 1e-3 * context->submit([&](gpu::Recorder& r) {
        for (int slot : toClear) r.fill(slices[slot], 0u);
        if (!toClear.empty()) r.barrier();
        toClear.clear();
        for (const auto& [m, slot] : targets) {
            glsl::ExposureStencilParams params{};
            params.nx = nx;
            params.ny = ny;
            params.halfWidth = halfWidths[m];
            params.paddedWidth = paddedWidth;
            params.padding = padding;
            params.columnPadding = columnPadding;
            r.dispatch(kernel, {&deposit, &weights[m], &rows[m], &slices[slot], &rowFlags}, &params,
                       groupsX, groupsY);
        }
    });
}
void TabulatedExposureEngine::GpuState::takeSlot(int slot, SurfaceGrid& out) {
    slices[slot].download(out.values.data(), uint64_t(nx) * ny * sizeof(float));
    toClear.push_back(slot);
}

void TabulatedExposureEngine::GpuState::clearSlots() {
    toClear.clear();
    for (int slot = 0; slot < int(slices.size()); ++slot) toClear.push_back(slot);
}

}  // namespace vpsim::exposure
