#pragma once
/// @file
/// 3D exposure of a layered print with the tabulated Monte Carlo beam kernel I(r, z) (seed 000
/// Eq. 11) instead of the fitted separable model: it keeps the sub-surface maximum and the
/// depth-dependent width that Eq. 12 smooths away.
///
/// Physics: a surface deposit cell of layer k' holds energy Q = S pitch^2 (mJ); it adds
/// Q I(r, d) / P (mJ/mm^2) to every voxel at horizontal distance r and depth d below the top of
/// layer k' (P: the kernel's incident power). With n voxel slices per layer of thickness h, slice s
/// of layer k <= k' lies at depth d = ((k' - k) n + s + 0.5) h / n, so each depth index
/// m = (k' - k) n + s has one 2D stencil w_m(di, dj) = pitch^2 <I(r, d_m)> / P (cell average of
/// 4 x 4 sub-samples) and the exposure is a sum of depth-sliced 2D convolutions (docs/PLATFORM.md).
///
/// Truncation: each stencil stops at the effective radius Reff(d) that holds all but 0.2% of the
/// power through its depth plane, and the stencils stop at the depth holding all but 0.2% of the
/// power summed over the slice depths; the energy beyond is dropped, not renormalised, and the
/// fraction kept (>= 99.5%) is keptEnergyFraction().
///
/// Layers are processed from the top down; accumulators are kept only for the layers still
/// receiving contributions, so memory is bounded by the kernel's depth, not the part's height.
/// Runs in a compute shader (shaders/exposure_stencil.comp) when given a Vulkan context and the
/// stencils are at most glsl::STENCIL_MAX_HALF_WIDTH cells wide each side, else on the CPU
/// (TBB-parallel over rows); the CPU indexes the stencils with exposure.glsl's stencilIndex.

#include <memory>
#include <vector>

#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::exposure {

/// Largest working memory (accumulators + stencils) the engine accepts, bytes.
constexpr double TABULATED_ENGINE_MAX_BYTES = 4.0 * (1ull << 30);

/// One depth's truncated 2D stencil: weights (dimensionless, exposure per unit deposit) on
/// (2 halfWidth + 1)^2 cell offsets, row-major, and per stencil row the largest |di| with a
/// non-zero weight (-1 for an empty row) so the circular support is not swept as a square.
struct DepthStencil {
    double depth = 0;   ///< mm below the source layer's top surface
    double radius = 0;  ///< mm, effective radius Reff at this depth
    int halfWidth = 0;  ///< cells
    std::vector<float> weights;
    std::vector<int> rowHalfWidth;
    float at(int di, int dj) const {
        return weights[size_t(dj + halfWidth) * (2 * halfWidth + 1) + size_t(di + halfWidth)];
    }
};

class TabulatedExposureEngine : public ExposureModel {
public:
    /// Builds the depth stencils from `kernel` (copied as needed; the kernel need not outlive the
    /// engine).
    /// @param grid the build-plane grid and voxel slices per layer
    /// @param kernel tabulated intensity I(r, z) in mW/mm^2 for incident power kernel.power (mW)
    /// @param layerThickness h, mm
    /// @param context a Vulkan context for the shader path, or nullptr for the CPU
    /// @throw InputError for an empty grid, a non-positive pitch, slice count, layer thickness or
    ///        power, or a kernel table that is empty, inconsistent in size, non-finite or all zero
    /// @throw ResourceError when the accumulators and stencils would exceed
    /// TABULATED_ENGINE_MAX_BYTES
    TabulatedExposureEngine(const ExposureGrid& grid, const kernel::BeamKernel& kernel,
                            double layerThickness, std::shared_ptr<gpu::Context> context = nullptr);
    ~TabulatedExposureEngine() override;

    std::string name() const override { return "tabulated"; }
    const ExposureGrid& grid() const override { return mGrid; }
    double layerThickness() const override { return mLayerThickness; }
    bool usesGpu() const override { return mGpu != nullptr; }

    /// The stencil of the voxel slice holding `depth` applied to `deposit` (CPU).
    SurfaceGrid layerMap(const SurfaceGrid& deposit, double depth) override;
    /// The same stencil applied as a correlation (offsets negated).
    SurfaceGrid layerMapAdjoint(const SurfaceGrid& map, double depth) override;
    /// Q_j = sum over the slices s of layers k <= j within the kernel's depth of the
    /// correlation of F_{k,s} with stencil (j - k) n + s (CPU).
    std::vector<SurfaceGrid> stackAdjoint(const ExposureField& field) override;

    /// Depth stencils, index m = depth index (slice depths (m + 0.5) h / n).
    const std::vector<DepthStencil>& stencils() const { return mStencils; }
    /// Layers whose accumulators are held at once: ceil(M / n) for M depth stencils.
    int layersInFlight() const { return mLayersInFlight; }
    /// Estimated working memory in bytes (accumulators + stencils + the deposit grid and its
    /// zero-bordered copy).
    double workingBytes() const { return mWorkingBytes; }
    /// Fraction of the kernel's energy (summed over the slice depths inside the table) that the
    /// truncated stencils keep.
    double keptEnergyFraction() const override { return mKeptEnergyFraction; }
    /// The widest stencil's half-width.
    int reachCells() const override;
    /// Depth stencils the shader applies to each deposit window it fetches (0 on the CPU path).
    int shaderStencilsPerInvocation() const;

private:
    struct GpuState;
    struct CpuGather;
    void buildStencils(const kernel::BeamKernel& kernel);
    void beginLayers(int layers) override;
    double addLayer(int k, SurfaceGrid& deposit) override;
    void emitLayer(int k, double top, const SliceSink& sink) override;
    /// Index of the stencil for `depth`, or -1 beyond the kernel's depth.
    int stencilIndexAt(double depth) const;

    std::unique_ptr<GpuState> mGpu;
    std::unique_ptr<CpuGather> mCpu;  ///< the CPU path's state, when there is no mGpu
    ExposureGrid mGrid;
    double mLayerThickness;
    std::vector<DepthStencil> mStencils;
    int mLayersInFlight = 1;
    double mWorkingBytes = 0;
    double mKeptEnergyFraction = 1.0;
    /// CPU path: a ring, layer k's slice s in slot (k mod L) n + s; shader path: the one grid
    /// that takes each finished slice from the device in turn.
    std::vector<SurfaceGrid> mAccumulators;
};

}  // namespace vpsim::exposure
