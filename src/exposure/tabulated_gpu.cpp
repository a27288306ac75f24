#include "exposure/tabulated_gpu.h"

#include "exposure/exposure_glsl.h"
#include "vpsim/shaders/exposure_stencil_spv.h"

namespace vpsim::exposure {
namespace {

std::vector<float> concatenated(const std::vector<DepthStencil>& stencils,
                                std::vector<uint32_t>& offsets) {
    std::vector<float> all;
    for (const auto& st : stencils) {
        offsets.push_back(uint32_t(all.size()));
        all.insert(all.end(), st.weights.begin(), st.weights.end());
    }
    return all;
}

}  // namespace

TabulatedExposureEngine::GpuState::GpuState(std::shared_ptr<gpu::Context> context_, int nx_,
                                            int ny_, const std::vector<DepthStencil>& stencils,
                                            int slots)
    : context(std::move(context_)),
      nx(uint32_t(nx_)),
      ny(uint32_t(ny_)),
      deposit(context, uint64_t(nx) * ny * sizeof(float)),
      weights(context,
              [&] {
                  uint64_t count = 0;
                  for (const auto& st : stencils) count += st.weights.size();
                  return count * sizeof(float);
              }()),
      kernel(context, exposure_stencil_spv, sizeof exposure_stencil_spv, 3,
             sizeof(glsl::ExposureStencilParams), {}, 64) {
    weights.upload(concatenated(stencils, offsets));
    for (const auto& st : stencils) halfWidths.push_back(st.halfWidth);
    for (int s = 0; s < slots; ++s) {
        slices.emplace_back(context, uint64_t(nx) * ny * sizeof(float));
        slices.back().fill(0u);
    }
}

double TabulatedExposureEngine::GpuState::addLayer(
    const SurfaceGrid& hostDeposit, const std::vector<std::pair<int, int>>& targets) {
    deposit.upload(hostDeposit.values);
    return 1e-3 * context->submit([&](gpu::Recorder& r) {
        for (const auto& [m, slot] : targets) {
            glsl::ExposureStencilParams params{};
            params.nx = nx;
            params.ny = ny;
            params.halfWidth = halfWidths[m];
            params.weightOffset = offsets[m];
            r.dispatch1D(kernel, {&deposit, &weights, &slices[slot]}, &params, uint64_t(nx) * ny);
        }
    });
}

void TabulatedExposureEngine::GpuState::takeSlot(int slot, SurfaceGrid& out) {
    slices[slot].download(out.values.data(), uint64_t(nx) * ny * sizeof(float));
    slices[slot].fill(0u);
}

}  // namespace vpsim::exposure
