#pragma once
/// @file
/// `xy_coupling: true`: all pixels of all layers optimised jointly through the projector's blur.
///
/// Seed 001 assumes no light transfer between pixels. With a blur (the job's blur_radius, a
/// Gaussian of that 1/e^2 radius) light from a pixel reaches its neighbours, so down-facing edges
/// and thin walls grow in XY. Here the doses d (one per pixel per layer) go through the shared
/// exposure model (exposure::ExposureEngine, fitted kernel: Gaussian blur, exponential
/// print-through with Dp): deposits U d on a grid `subsamples` times finer than the pixels (U
/// repeats a pixel's dose over its cells), E = stack(U d) at each layer's mid-depth (where the
/// run's validation measures the XY contour), A d = -K E.
///
/// The joint objective aims at the shape (the gel-point criterion of `objective: geometric`,
/// applied to every cell in 3D rather than to each column's nodes), in units of the gel dose Ec:
///   J(d) = [ sum_cells w_c h_c^2 + beta sum_inside u_c^2 ] / N_inside,
///   h_c = max(0, (1 + margin) - E_c/Ec) inside the part, max(0, E_c/Ec - (1 - margin)) outside,
///   u_c = (E_c - E_t) / E_t inside (uniformity; E_t is the conversion-l2 target dose
///         -ln(1 - Phi_obj)/K, or the warm start's mean inside dose for `geometric`),
/// with w_c = 1 + contourWeight for cells within contourCells of a solid/void change (in the
/// layer, or against the layer above or below), else 1. A squared hinge: smooth, convex, zero
/// wherever the cell is safely on its side of the gel point.
///
/// Warm start: the column optimum of the chosen objective. Each pixel keeps an exposure pattern
/// (which layers get light) and Eq. 10's bounds for it; with conversion-l2 the pattern of each
/// pixel is taken from the conversion-l2 or the geometric column optimum, whichever scores lower
/// on the pixel's own column (no blur), because no dose inside the conversion-l2 pattern can
/// stop its print-through below a down-facing surface. The start is the best (in J) of the column
/// optimum, the geometric one and that mix. The doses then move within their boxes by accelerated
/// projected gradient (FISTA with a gradient restart; step 1/L, L from a power iteration on
/// A^T A), and the best point evaluated is returned, so J never exceeds the warm start's.
/// Units: mm, dose mJ/mm^2.

#include <memory>
#include <string>

#include "vpsim/optimise/dlp/part.h"

namespace vpsim::optimise {

struct DlpXyOptions {
    double pixelPitch = 0.0625;  ///< mm
    double blurRadius = 0.04;    ///< mm, 1/e^2 radius of the projector blur (> 0)
    int subsamples = 2;          ///< grid cells per pixel along x and y (>= 1)
    int iterations = 60;         ///< FISTA iterations
    double margin = 0.05;        ///< inside cells >= (1 + margin) Ec, outside <= (1 - margin) Ec
    double contourWeight = 4.0;  ///< extra weight of cells near a solid/void change (>= 0)
    int contourCells = 2;        ///< "near": within this many cells in x or y (>= 0)
    double uniformityWeight = 0.01;   ///< beta (>= 0)
    bool tryGeometricPattern = true;  ///< conversion-l2: also start from the geometric pattern
};

struct DlpXyResult {
    DlpPartResult doses;             ///< jointly optimised doses (same layout as the columns')
    std::string start;               ///< the warm start: "columns", "geometric" or "mixed"
    double objectiveColumns = 0.0;   ///< J of the chosen objective's column optimum
    double objectiveStart = 0.0;     ///< J of the warm start (<= objectiveColumns)
    double objectiveXy = 0.0;        ///< J of the joint optimum (<= objectiveStart)
    int iterations = 0;              ///< FISTA iterations run
    double uniformityTarget = 0.0;   ///< E_t of J, mJ/mm^2
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

/// The joint objective J of the file comment on a part, for the optimiser and its tests.
class DlpShapeObjective {
public:
    /// @param uniformityTarget E_t, mJ/mm^2 (> 0)
    /// @throw InputError on bad sizes or parameters
    DlpShapeObjective(const DlpLayerStack& part, const DlpColumnProblem& problem,
                      const DlpXyOptions& options, double uniformityTarget);
    ~DlpShapeObjective();
    /// J(dose) (dose per layer, per pixel, mJ/mm^2); with `gradient`, also dJ/d(dose).
    double value(const std::vector<std::vector<float>>& dose,
                 std::vector<std::vector<float>>* gradient = nullptr);
    /// Mean over layers with solid cells of (misclassified cell area) / (solid perimeter), mm:
    /// the XY contour displacement at the layers' mid-depth, cured where E >= Ec.
    double contourError(const std::vector<std::vector<float>>& dose);
    /// Largest eigenvalue bound of J's Hessian (the FISTA step is its inverse).
    double lipschitz(const std::vector<std::vector<float>>& start);
    DlpBlurOperator& blur();

private:
    struct State;
    std::unique_ptr<State> mState;
};

/// Mean dose at the inside cells' mid-depth without blur (mJ/mm^2): E_t for `geometric`.
double meanInsideDose(const DlpLayerStack& part, const DlpColumnProblem& problem,
                      const DlpPartResult& doses);

/// Joint optimisation starting from the column optimum `columns` (computed when null).
/// @throw InputError as optimiseDlpPart or on bad options
DlpXyResult optimiseDlpPartXy(const DlpLayerStack& part, const DlpPartOptions& options,
                              const DlpXyOptions& xy, const DlpPartResult* columns = nullptr);

}  // namespace vpsim::optimise
