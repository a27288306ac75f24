#include "exposure/tabulated_gpu.h"

#include <algorithm>

#include "exposure/exposure_glsl.h"
#include "vpsim/core/error.h"
#include "vpsim/shaders/exposure_stencil_spv.h"

namespace vpsim::exposure {
namespace {

constexpr int ROWS = 8;                          ///< STENCIL_ROWS of exposure_stencil.comp
constexpr int GROUP = 64;                        ///< its local_size_x
constexpr uint64_t WEIGHT_BLOCK_FLOATS = 16384;  ///< its Weights block: vec4[4096]

int roundUp(int n, int m) {
    return (n + m - 1) / m * m;
}

/// The stencil's weights at half-width H >= st.halfWidth (zeros outside), row-major, in a block
/// of WEIGHT_BLOCK_FLOATS.
std::vector<float> weightBlock(const DepthStencil& st, int H) {
    std::vector<float> block(WEIGHT_BLOCK_FLOATS, 0.0f);
    for (int dj = -st.halfWidth; dj <= st.halfWidth; ++dj)
        for (int di = -st.halfWidth; di <= st.halfWidth; ++di)
            block[size_t(glsl::stencilIndex(di, dj, H))] = st.at(di, dj);
    return block;
}

/// Per stencil column di (index di + H): the first and last row index t = dj + H with a non-zero
/// weight (0 and -1 for an empty column), two columns per ivec4, in a block of
/// STENCIL_COLUMN_BLOCK columns.
std::vector<int32_t> columnBlock(const DepthStencil& st) {
    std::vector<int32_t> block(2 * glsl::STENCIL_COLUMN_BLOCK, 0);
    const int H = st.halfWidth;
    for (int di = -H; di <= H; ++di) {
        int first = 0, last = -1;
        for (int dj = -H; dj <= H; ++dj)
            if (st.at(di, dj) != 0.0f) {
                if (last < first) first = dj + H;
                last = dj + H;
            }
        block[size_t(2 * (di + H))] = first;
        block[size_t(2 * (di + H) + 1)] = last;
    }
    return block;
}

int paddedHalfWidth(const DepthStencil& st) {
    return st.halfWidth;
}

int largestHalfWidth(const std::vector<DepthStencil>& stencils) {
    int H = 0;
    for (const auto& st : stencils) H = std::max(H, paddedHalfWidth(st));
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
      paddedWidth(uint32_t(roundUp(nx_, GROUP) + 2 * padding)),
      // The shader's window reads one row past the last stencil row.
      deposit(context,
              uint64_t(paddedWidth) * (roundUp(ny_, ROWS) + 2 * padding + 1) * sizeof(float)),
      kernel(context, exposure_stencil_spv, sizeof exposure_stencil_spv,
             {gpu::Binding::UniformTexels, gpu::Binding::Uniform, gpu::Binding::Uniform,
              gpu::Binding::Storage},
             sizeof(glsl::ExposureStencilParams), {}, GROUP) {
    for (const auto& st : stencils) {
        const int H = paddedHalfWidth(st);
        if (uint64_t(2 * H + 1) * (2 * H + 1) > WEIGHT_BLOCK_FLOATS)
            throw ResourceError("a tabulated stencil of half-width " + std::to_string(H) +
                                " cells exceeds the shader's 64 KiB weight block (half-width "
                                "63); use a coarser pitch or the CPU path");
        halfWidths.push_back(H);
        weights.emplace_back(context, WEIGHT_BLOCK_FLOATS * sizeof(float));
        weights.back().upload(weightBlock(st, H));
        columns.emplace_back(context, 2 * glsl::STENCIL_COLUMN_BLOCK * sizeof(int32_t));
        columns.back().upload(columnBlock(st));
    }
    deposit.fill(0u);  // the border stays zero: uploads write the grid's cells only
    for (int s = 0; s < slots; ++s) slices.emplace_back(context, uint64_t(nx) * ny * sizeof(float));
    clearSlots();
}

double TabulatedExposureEngine::GpuState::addLayer(
    const SurfaceGrid& hostDeposit, const std::vector<std::pair<int, int>>& targets) {
    deposit.uploadRows(hostDeposit.values.data(), nx * sizeof(float), ny, nx * sizeof(float),
                       (uint64_t(padding) * paddedWidth + padding) * sizeof(float),
                       paddedWidth * sizeof(float));
    const uint32_t groupsX = (nx + GROUP - 1) / GROUP, groupsY = (ny + ROWS - 1) / ROWS;
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
            r.dispatch(kernel, {&deposit, &weights[m], &columns[m], &slices[slot]}, &params,
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
