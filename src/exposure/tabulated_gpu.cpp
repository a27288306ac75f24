#include "exposure/tabulated_gpu.h"

#include <algorithm>
#include <cstring>

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
      padded(size_t(paddedWidth) * size_t(roundUp(ny_, ROWS) + 2 * padding + 1), 0.0f),
      deposit(context, padded.size() * sizeof(float)),
      kernel(context, exposure_stencil_spv, sizeof exposure_stencil_spv,
             {gpu::Binding::UniformTexels, gpu::Binding::Uniform, gpu::Binding::Storage},
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
    }
    for (int s = 0; s < slots; ++s) {
        slices.emplace_back(context, uint64_t(nx) * ny * sizeof(float));
        slices.back().fill(0u);
    }
}

double TabulatedExposureEngine::GpuState::addLayer(
    const SurfaceGrid& hostDeposit, const std::vector<std::pair<int, int>>& targets) {
    for (uint32_t j = 0; j < ny; ++j)
        std::memcpy(padded.data() + (size_t(j) + padding) * paddedWidth + padding,
                    hostDeposit.values.data() + size_t(j) * nx, nx * sizeof(float));
    deposit.upload(padded);
    const uint32_t groupsX = (nx + GROUP - 1) / GROUP, groupsY = (ny + ROWS - 1) / ROWS;
    return 1e-3 * context->submit([&](gpu::Recorder& r) {
        for (const auto& [m, slot] : targets) {
            glsl::ExposureStencilParams params{};
            params.nx = nx;
            params.ny = ny;
            params.halfWidth = halfWidths[m];
            params.paddedWidth = paddedWidth;
            params.padding = padding;
            r.dispatch(kernel, {&deposit, &weights[m], &slices[slot]}, &params, groupsX, groupsY);
        }
    });
}

void TabulatedExposureEngine::GpuState::takeSlot(int slot, SurfaceGrid& out) {
    slices[slot].download(out.values.data(), uint64_t(nx) * ny * sizeof(float));
    slices[slot].fill(0u);
}

}  // namespace vpsim::exposure
