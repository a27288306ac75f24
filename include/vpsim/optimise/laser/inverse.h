#pragma once
/// @file
/// Planner `inverse` (issue 11 item 5, beyond seed 000): the whole layer at once. Every dot of a
/// grid (pitch `dotPitch`, on planning-grid cell centres) carries an energy x_k >= 0; the
/// layer's surface exposure is E = M S x (S: dot energies to the surface deposit, M: the exposure
/// model's layerMap at depth 0). The objective is the seed's exposure error on the layer's total
/// surface exposure, with unit weight on every cell of the part grown by Reff:
///
///     f(x) = 1/2 sum_cells (E(x) + E_t - Etm)^2,   Etm = Etar inside the part, 0 outside,
///
/// E_t the exposure the layers above transmit (Eq. 21; top-down compensation, the same as DFBTP:
/// with compensation off E_t = 0). Its gradient is S' M' (E + E_t - Etm) through the model's
/// adjoint (layerMapAdjoint). Solved by projected gradient with Nesterov acceleration (FISTA,
/// step 1/L with L the largest row sum of the non-negative S'M'WMS, restarted when f rises),
/// warm-started from the ACES plan (base.aces; cure-at-contour in jobs) gathered onto the dots,
/// first `coarseIterations` on a grid whose cells are the dots (the same objective sampled at
/// the dot pitch: stride^2 fewer cells and a stride times shorter blur), then `iterations` on
/// the planning grid. The best iterate is
/// kept, and if it is not below the ACES plan's own error the ACES plan is returned: never worse
/// than ACES. Curved edges and arbitrary corners need no special treatment. Units: mm, mJ, mJ/mm^2.

#include <vector>

#include "vpsim/optimise/laser/dfbtp.h"

namespace vpsim::optimise {

struct InverseParameters {
    /// Beam, process, grid pitch and compensation as for DFBTP (its liftings are not used);
    /// base.aces also designs the ACES warm start with its own edge rule and border loops
    /// (readInverseKeys() defaults it to cure-at-contour).
    DfbtpParameters base;
    double dotPitch = 0.02;  ///< mm, rounded to a whole number of grid cells
    int iterations = 30;     ///< projected-gradient iterations per layer on the planning grid
    /// Iterations first on the coarse grid whose cells are the dots (stride^2 fewer cells, so
    /// each costs about 1/stride^3 of a fine one); 0 skips the coarse stage.
    int coarseIterations = 40;
};

struct InverseLayerReport {
    double acesObjective = 0;   ///< f of the ACES plan (mJ^2/mm^4, the seed's SSE / 2)
    double startObjective = 0;  ///< f of the warm start (ACES gathered onto the dots)
    double finalObjective = 0;  ///< f of the returned plan
    int iterations = 0, dots = 0;
    bool keptAces = false;  ///< the optimisation did not beat ACES: ACES returned
};

struct InverseResult {
    plan::ScanPlan plan;
    std::vector<LayerCompensation> compensation;  ///< bottom first
    std::vector<InverseLayerReport> layers;       ///< bottom first
    double targetDose = 0;
};

/// Plans every layer from the top down (regions bottom first; tops[k] layer k's top, mm).
/// @throw InputError for impossible parameters
InverseResult planInverse(const std::vector<geometry::PolygonSet>& regions,
                          const std::vector<double>& tops, const InverseParameters& parameters,
                          const kernel::FittedBeam& beam, exposure::ExposureModel* model = nullptr);

}  // namespace vpsim::optimise
