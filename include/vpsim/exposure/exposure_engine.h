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
/// The blur and the recursion run in compute shaders (shaders/exposure_blur.comp,
/// shaders/exposure_recursion.comp) or on the CPU from the same GLSL
/// (shaders/include/exposure.glsl).

#include <functional>
#include <memory>

#include "vpsim/exposure/surface_grid.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::gpu {
class Context;
}

namespace vpsim::exposure {

/// The separable (fitted) beam kernel of seed 000 Eq. 12.
struct SeparableBeam {
    double radius = 0.05;            ///< mm, 1/e^2 intensity radius (We3D)
    double attenuationLength = 0.1;  ///< mm, 1/e depth of the exposure (De3D)
    /// Surface exposure per delivered energy relative to a lossless Gaussian: the fitted
    /// amplitude Ie3D(0,0) pi We3D^2 / (2 P) of a Monte Carlo kernel (reflection losses and
    /// scattering lower it), 1 for an ideal beam.
    double efficiency = 1.0;
};

/// The build-volume grid the exposure is computed on.
struct ExposureGrid {
    int nx = 0, ny = 0;               ///< cells in x and y
    double originX = 0, originY = 0;  ///< mm, corner of cell (0, 0)
    double pitch = 0.01;              ///< mm, cell size in x and y
    int slicesPerLayer = 1;           ///< voxel slices per layer thickness (voxel z size h / n)
    /// Cells needed to cover [xmin, xmax] x [ymin, ymax] plus `margin` (mm) on every side.
    static ExposureGrid covering(double xmin, double ymin, double xmax, double ymax, double margin,
                                 double pitch, int slicesPerLayer);
};

/// One finished voxel slice: layer index, slice index within the layer (0 = top), the height of
/// the slice centre (mm) and the exposure (mJ/mm^2) on the x-y grid, row-major.
struct ExposureSlice {
    int layer = 0;
    int slice = 0;
    double z = 0;
    const SurfaceGrid* values = nullptr;
};
using SliceSink = std::function<void(const ExposureSlice&)>;

/// Half-width of the truncated blur in cells: 3.5 sigma = 1.75 W keeps all but ~2e-6 of the
/// Gaussian's weight (renormalised, so energy is conserved exactly up to float rounding).
int blurHalfWidth(double radius, double pitch);

class ExposureEngine {
public:
    /// @param context a Vulkan context for the shader path, or nullptr for the CPU path
    /// @throw InputError for impossible parameters; ResourceError when a grid is too large
    ExposureEngine(const ExposureGrid& grid, const SeparableBeam& beam, double layerThickness,
                   std::shared_ptr<gpu::Context> context = nullptr);
    ~ExposureEngine();

    /// Exposes every layer of `plan` (layer k's top at plan.layers[k].z) and calls `sink` for each
    /// voxel slice from the top of the part down. Returns the time spent in the blur and
    /// recursion (seconds, GPU time on the shader path).
    double run(const plan::ScanPlan& plan, const SliceSink& sink);

    /// One layer's exposure map B = G_W * S (exposed on its own, no print-through).
    SurfaceGrid exposureMap(const SurfaceGrid& deposit);

    const ExposureGrid& grid() const { return mGrid; }
    bool usesGpu() const { return mGpu != nullptr; }

private:
    struct GpuState;
    void blurAndAccumulate(SurfaceGrid& deposit, SurfaceGrid& running, float decay,
                           double& seconds);
    ExposureGrid mGrid;
    SeparableBeam mBeam;
    double mLayerThickness;
    std::unique_ptr<GpuState> mGpu;
};

}  // namespace vpsim::exposure
