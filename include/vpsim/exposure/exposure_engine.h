#pragma once
/// @file
/// 3D exposure of a layered print, with print-through (seed 000 Eq. 21, seed 001 Eq. 4).
///
/// The fitted beam kernel is separable: a normalised Gaussian in x and y (1/e^2 radius W) times an
/// exponential in depth (attenuation length De). So, per layer k, the exposure map is the layer's
/// surface deposit S_k blurred by two 1D Gaussian passes, B_k = G_W * S_k, and the exposure at
/// depth d below the top of layer k, summed over that layer and every later layer j above it, is
///   E_k(d) = exp(-d/De) R_k,   R_k = B_k + a R_{k+1},   a = exp(-h/De)   (h: layer thickness),
/// the recursion form of Eq. 21 (E_t,i = sum_j E_map,j exp(-lt (j - i)/De)). Layers are processed
/// from the top down, so memory holds two 2D grids whatever the number of layers; each finished
/// slice goes to a sink (statistics, an OpenVDB grid, pictures) and is not kept.
///
/// The blur and the recursion run in a compute shader (shaders/exposure_blur.comp, two passes,
/// the second ending with the recursion step) or on the CPU from the same GLSL
/// (shaders/include/exposure.glsl).

#include <memory>

#include "vpsim/exposure/exposure_model.h"
#include "vpsim/kernel/fitted_beam.h"

namespace vpsim::gpu {
class Context;
}

namespace vpsim::exposure {

/// Half-width of the truncated blur in cells: 3.5 sigma = 1.75 W keeps all but ~2e-6 of the
/// Gaussian's weight (renormalised, so energy is conserved exactly up to float rounding).
int blurHalfWidth(double radius, double pitch);

/// The fitted-kernel exposure model (separable blur plus the print-through recursion).
class ExposureEngine : public ExposureModel {
public:
    /// @param context a Vulkan context for the shader path, or nullptr for the CPU path
    /// @throw InputError for impossible parameters; ResourceError when a grid is too large
    ExposureEngine(const ExposureGrid& grid, const kernel::FittedBeam& beam, double layerThickness,
                   std::shared_ptr<gpu::Context> context = nullptr);
    ~ExposureEngine() override;

    std::string name() const override { return "fitted"; }
    const ExposureGrid& grid() const override { return mGrid; }
    double layerThickness() const override { return mLayerThickness; }
    bool usesGpu() const override { return mGpu != nullptr; }
    int reachCells() const override { return blurHalfWidth(mBeam.radius, mGrid.pitch); }
    const kernel::FittedBeam& beam() const { return mBeam; }

    /// One layer's surface exposure map B = G_W * S (exposed on its own, no print-through):
    /// layerMap(deposit, 0).
    SurfaceGrid exposureMap(const SurfaceGrid& deposit) { return layerMap(deposit, 0.0); }
    /// exp(-depth/De) G_W * S.
    SurfaceGrid layerMap(const SurfaceGrid& deposit, double depth) override;
    /// The blur is symmetric, so the adjoint is the same map.
    SurfaceGrid layerMapAdjoint(const SurfaceGrid& map, double depth) override;
    /// Q_j = G_W * V_j with V_j = U_j + a V_{j-1} and U_k = sum_s exp(-d_s/De) F_{k,s}: the
    /// recursion of the forward operator run from the bottom up.
    std::vector<SurfaceGrid> stackAdjoint(const ExposureField& field) override;

private:
    struct GpuState;
    void beginLayers(int layers) override;
    double addLayer(int k, SurfaceGrid& deposit) override;
    void emitLayer(int k, double top, const SliceSink& sink) override;
    /// The blur's half-width (cells), standard deviation (cells) and the passes' divisors.
    struct Blur {
        int halfWidth;
        float sigmaCells, normX, normY;
    };
    Blur blurOf() const;
    /// Blurs `deposit` in place and updates running = B + decay running, on the CPU; `pass`
    /// holds the first pass (sized here when it is not the deposit's size).
    void blurAndAccumulateCpu(SurfaceGrid& deposit, SurfaceGrid& running, float decay,
                              double& seconds, SurfaceGrid& pass);

    ExposureGrid mGrid;
    kernel::FittedBeam mBeam;
    double mLayerThickness;
    std::unique_ptr<GpuState> mGpu;
    SurfaceGrid mRunning, mSlice;  ///< the recursion's running sum, the slice handed to sinks
    /// The running sum the slices are made from: mRunning, or the shader path's R in host memory
    /// (no copy; layerMap copies it to mRunning before it blurs over it), in rows mRunningStride
    /// cells apart.
    const float* mRunningView = nullptr;
    size_t mRunningStride = 0;
    SurfaceGrid mPass;        ///< the blur's first pass, kept from layer to layer
    bool mGpuRestart = true;  ///< the next layer starts the running deposit afresh
};

}  // namespace vpsim::exposure
