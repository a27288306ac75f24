#pragma once
/// @file
/// `xy_coupling: true`: all pixels of all layers optimised jointly through the projector's blur.
///
/// Seed 001 assumes no light transfer between pixels. With a blur (the job's blur_radius, a
/// Gaussian of that 1/e^2 radius) light from a pixel reaches its neighbours, so down-facing edges
/// and thin walls grow in XY. Here the doses d (one per pixel per layer) go through the shared
/// exposure model (exposure::ExposureEngine, fitted kernel: Gaussian blur, exponential
/// print-through with Dp): deposits U d on a grid `subsamples` times finer than the pixels (U
/// repeats a pixel's dose over its cells), E = stack(U d) at each layer's mid-depth, phi = -K E,
/// and F = sum over cells of (phi - phi_obj)^2 / subsamples^2 (targets of Eq. 11-12 per cell).
/// The exposure pattern and Eq. 10 bounds of every pixel are kept from the column optimum, and
/// the doses move within their boxes by accelerated projected gradient (FISTA; gradient
/// -2K U^T stackAdjoint(phi - phi_obj)), step 1/L with L from a power iteration on A^T A.
/// Units: mm, dose mJ/mm^2.

#include <memory>

#include "vpsim/optimise/dlp_part.h"

namespace vpsim::optimise {

struct DlpXyOptions {
    double pixelPitch = 0.0625;  ///< mm
    double blurRadius = 0.04;    ///< mm, 1/e^2 radius of the projector blur (> 0)
    int subsamples = 2;          ///< grid cells per pixel along x and y (>= 1)
    int iterations = 60;         ///< FISTA iterations
};

struct DlpXyResult {
    DlpPartResult doses;             ///< jointly optimised doses (same layout as the columns')
    double objectiveColumns = 0.0;   ///< F through the blur of the column optimum
    double objectiveXy = 0.0;        ///< F of the joint optimum
    double contourErrorColumns = 0;  ///< mm, mean XY contour displacement, column optimum
    double contourErrorXy = 0.0;     ///< mm, the same for the joint optimum
    double seconds = 0.0;            ///< wall time of the joint optimisation
    double peakFieldMiB = 0.0;       ///< memory of the 3D fields held
};

/// The linear operator A d = -K stack(U d) (one value per cell and layer) and its adjoint, for
/// the joint problem and its tests.
class DlpBlurOperator {
public:
    /// @throw InputError on bad sizes or parameters
    DlpBlurOperator(int width, int height, int layers, const DlpColumnProblem& problem,
                    const DlpXyOptions& options);
    ~DlpBlurOperator();
    /// d: per layer, width x height pixel doses -> per layer, cells of the fine grid.
    std::vector<std::vector<float>> apply(const std::vector<std::vector<float>>& dose);
    /// The adjoint: per layer cells -> per layer pixels.
    std::vector<std::vector<float>> applyAdjoint(const std::vector<std::vector<float>>& cells);
    int cellsX() const;
    int cellsY() const;
    /// Cell (i, j)'s pixel, or -1 in the margin around the part.
    long pixelOf(int i, int j) const;

private:
    struct State;
    std::unique_ptr<State> mState;
};

/// Joint optimisation starting from the column optimum `columns` (computed when null).
/// @throw InputError as optimiseDlpPart or on bad options
DlpXyResult optimiseDlpPartXy(const DlpLayerStack& part, const DlpPartOptions& options,
                              const DlpXyOptions& xy, const DlpPartResult* columns = nullptr);

}  // namespace vpsim::optimise
