#pragma once
/// @file
/// The inverse planner's shape objective (issue 23 item 2; the laser counterpart of the DLP
/// geometric objective): every dot energy of every layer at once, judged on what cures in 3D.
/// The exposure of the whole stack E = A x (A: dots to per-layer surface deposits, then the
/// exposure model's stack operator with print-through) is compared with the critical dose Ec at
/// every voxel of the planning grid (slicesPerLayer slices per layer, the validation's slice
/// centres):
///
///     J(x) = V/2 sum_v w_v (h_v(E_v) / Ec)^2 + V/2 mu sum_{v inside} ((E_v - Ebar) / Ec)^2,
///     h_v = max(0, (1 + m_v) Ec - E_v) inside the part, max(0, E_v - (1 - m_v) Ec) outside,
///
/// V the voxel volume (mm^3, so J does not depend on the resolution), m_v = m min(1, d_v / p)
/// the margin growing with the voxel centre's distance d_v to the part's surface (2D in its
/// slice, and vertically to the state change above or below) up to the grid pitch p, so the
/// Ec crossing is aimed at the surface itself; w_v = 1, plus `wallWeight` within `wallBand` of
/// a wall, plus `downFacingWeight` outside the part below a down-facing surface (within 3 De3D:
/// the over-cure below overhangs), scaled per slice by levelTargets(); Ebar the start's mean
/// exposure inside (a small uniformity term, weight mu). J is convex (hinge squares of a linear
/// map); its gradient is A' (dJ/dE) through the model's stackAdjoint, so print-through is
/// compensated inside the model and not layer by layer. Solved by FISTA with projection onto x >= 0
/// in the metric of the row sums of A'(W + mu)A V / Ec^2 (a step per dot), restarted when J rises;
/// warm-started from a given plan (the job's ACES) gathered bilinearly onto the dots. The returned
/// plan is never worse than the start on J, measured on the plans themselves: if the best iterate
/// is not below J(start), the start is returned. Units: mm, mJ, mJ/mm^2.

#include <functional>
#include <memory>
#include <vector>

#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/polygons.h"
#include "vpsim/kernel/fitted_beam.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::optimise {

struct ShapeParameters {
    double margin = 0.05;            ///< m: inside E >= (1 + m) Ec, outside E <= (1 - m) Ec
    double wallWeight = 4.0;         ///< extra weight within wallBand of a wall
    double wallBand = 0.03;          ///< mm
    double downFacingWeight = 16.0;  ///< extra weight below down-facing surfaces (outside)
    double uniformity = 0.01;        ///< mu
    int slicesPerLayer = 5;          ///< objective voxel slices per layer
    int iterations = 60;             ///< FISTA iterations on all layers at once, planning grid
    /// Iterations first on the grid whose cells are the dots (the same variables, each about
    /// 1/stride^3 of a fine one); 0 skips it.
    int coarseIterations = 800;
    /// mm: 0 moves every mark of the start onto the dots; > 0 optimises only the dots within
    /// this distance of each layer's contour (the edges), onto which the start's marks there
    /// move (a dot, or a vector whose every point is that near), the other marks held as they
    /// are (DFBTP's middle area with `edges: shape`).
    double edgeBand = 0;
    /// mm: the dots lie on rows this far apart (rounded down to a whole number of dot pitches,
    /// at least one), the dot pitch along them; along x or y per layer, whichever gives fewer
    /// scan lines (alternating by layer where both give about as many), odd layers' rows between
    /// even layers'. Each row is a scan line of power-modulated marks on the machine, so rows
    /// near ACES's hatch spacing keep the build time near ACES's (issue 23).
    double rowSpacing = 0;
};

/// Per-voxel targets of J on a grid's voxel slices (index k n + s, as an ExposureField).
struct ShapeTargets {
    std::vector<std::vector<char>> inside;   ///< per slice, per cell
    std::vector<std::vector<float>> bound;   ///< (1 + m_v) Ec inside, (1 - m_v) Ec outside
    std::vector<std::vector<float>> weight;  ///< w_v
    double criticalDose = 0;                 ///< Ec, mJ/mm^2
    double voxelVolume = 0;                  ///< mm^3
    double uniformity = 0, meanInside = 0;   ///< mu (see levelTargets), Ebar (mJ/mm^2)
};

/// Targets from the part's cross-section at every voxel slice centre (`sliceRegions`, index
/// k n + s, slice 0 at the layer's top) on `grid` (its slicesPerLayer = n).
ShapeTargets shapeTargets(const exposure::ExposureGrid& grid, double layerThickness,
                          double attenuationLength,
                          const std::vector<geometry::PolygonSet>& sliceRegions,
                          double criticalDose, const ShapeParameters& parameters);

/// Scales each slice's hinge weights by (Ec / L)^2, L the start's mean exposure inside the part
/// in that slice (at least Ec): a violation's geometric size is about h / |grad E|, and the
/// exposure's slope near a wall grows with its level (the top of a layer in a strongly
/// absorbing slurry receives several Ec), so the residuals count about as distances. Also sets
/// Ebar, the uniformity term's level, to the start's mean exposure inside (at least Ec), and
/// mu to mu (Ec / Ebar)^2, so the uniformity term is mu V/2 sum ((E - Ebar) / Ebar)^2.
void levelTargets(ShapeTargets& targets, const exposure::ExposureField& start);

/// J of a 3D exposure field, and dJ/dE (a field) when `gradient` is not null.
double shapeObjective(const ShapeTargets& targets, const exposure::ExposureField& field,
                      exposure::ExposureField* gradient = nullptr);

/// J as a function of the dot energies (mJ) of every layer: dots[k] are cell indices of layer
/// k's deposit grid; x is all layers' energies, layer 0 first.
class ShapeProblem {
public:
    ShapeProblem(exposure::ExposureModel& model, const ShapeTargets& targets,
                 std::vector<std::vector<size_t>> dots);
    size_t size() const { return mSize; }
    /// Deposits held as they are (mJ/mm^2 per layer: the marks the dots do not take over),
    /// added to every x's; none by default.
    void holdFixed(std::vector<exposure::SurfaceGrid> fixed) { mFixed = std::move(fixed); }
    /// The per-layer deposits of x (mJ/mm^2), the fixed ones included.
    std::vector<exposure::SurfaceGrid> deposits(const std::vector<double>& x) const;
    double value(const std::vector<double>& x) const;
    /// The 3D exposure field of x.
    exposure::ExposureField field(const std::vector<double>& x) const;
    /// J of the field of some x, and its gradient with respect to x when `gradient` is given.
    double valueAt(const exposure::ExposureField& field, std::vector<double>* gradient) const;
    /// J and its gradient with respect to x.
    double valueAndGradient(const std::vector<double>& x, std::vector<double>& gradient) const;
    /// J of per-layer deposits (any plan's, e.g. ACES vectors).
    double valueOfDeposits(const std::vector<exposure::SurfaceGrid>& deposits) const;
    /// The Hessian's row sums, diag(H 1) (times 1.001 for float rounding): H is non-negative, so
    /// diag(H 1) - H is diagonally dominant and the diagonal majorises H; a step of 1 / row sum
    /// per variable is a valid (preconditioned) gradient step.
    std::vector<double> rowSums() const;
    const std::vector<std::vector<size_t>>& dots() const { return mDots; }

private:
    exposure::ExposureModel& mModel;
    const ShapeTargets& mTargets;
    std::vector<std::vector<size_t>> mDots;
    std::vector<exposure::SurfaceGrid> mFixed;
    std::vector<size_t> mOffset;  ///< first variable of each layer
    /// The dots' deposits alone (the linear part of the map).
    std::vector<exposure::SurfaceGrid> dotDeposits(const std::vector<double>& x) const;
    size_t mSize = 0;
    double mCellArea = 0;
};

struct ShapeResult {
    plan::ScanPlan plan;
    double objectiveStart = 0;  ///< J of the start plan
    double objectiveFinal = 0;  ///< J of the returned plan
    double objectiveDots = 0;   ///< J of the start gathered onto the dots
    bool keptStart = false;     ///< the optimisation did not beat the start: start returned
    int iterations = 0;
    size_t dots = 0;
};

/// Turns a plan of dots into what the machine runs (plan::fitPlanToLimits: dot rows as
/// power-modulated vectors, negligible dots dropped).
using MachineFit = std::function<void(plan::ScanPlan&)>;

/// The shape objective's grid: planningGrid(regions, beamRadius, pitch) widened by one cell to
/// the lattice of multiples of the pitch, the lattice the simulation's voxels lie on
/// (geometry::RasterGrid::covering), so that a wall on it lies half way between two voxel
/// centres. The objective's bounds are one-sided and its voxels rasterised at their centres, so
/// the Ec crossing may settle anywhere between the voxel centres beside a wall; off the lattice
/// those sat 0.87 um outside and 9.13 um inside laser-pillars' walls (on round coordinates) and
/// every wall cured about 4 um towards +x and +y (IoU 0.9475 against 0.9652 on the lattice).
exposure::ExposureGrid shapePlanningGrid(const std::vector<geometry::PolygonSet>& regions,
                                         double beamRadius, double pitch);

/// Plans every layer at once from `start` (one layer per region, bottom first; its layer z are
/// kept). The optimised dots go through `toMachine` (when given) before the returned plan is
/// measured against the start, so J_final is the objective of the plan the machine runs. `regions`
/// give the dots' area (within half a dot pitch); `sliceRegions` the part at every objective slice
/// (see shapeTargets). Dots on every `dotPitch` / `gridPitch`-th cell of
/// shapePlanningGrid(regions, We3D, gridPitch).
/// @throw InputError for impossible parameters
ShapeResult planInverseShape(const std::vector<geometry::PolygonSet>& regions,
                             const std::vector<geometry::PolygonSet>& sliceRegions,
                             const plan::ScanPlan& start, double gridPitch, double dotPitch,
                             const ShapeParameters& parameters, const kernel::FittedBeam& beam,
                             double layerThickness, double criticalDose,
                             const MachineFit& toMachine = {});

}  // namespace vpsim::optimise
