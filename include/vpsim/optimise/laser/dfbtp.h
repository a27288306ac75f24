#pragma once
/// @file
/// Disassembled-feature-based trajectory planning, DFBTP (seed 000 Section III): per layer, the
/// middle area with ACES (the seed's 5% Ep edge rule, App. A), then every linear edge as a 1D
/// least-squares QP across the edge (Eq. 17), then every corner as a 2D QP over dots (Eq. 19),
/// each on the exposure still missing after the features planned before it; layers
/// planned from the top down, each aiming at its target minus what the layers above transmit
/// into it (Eq. 21-22).
///
/// The QPs (optimise/qp_active_set.h): minimise |K T - E_c|^2 over T >= 0 subject to
/// K T <= E_c + a_i Etar at every evaluation point. The seed gives no a_i; vpsim's defaults:
///   a_out = 0.15 outside the part (sub-blocks 1, 5): with the middle area's 5% tail the surface
///               outside stays below 0.2 Etar, below Ec/Etar = exp(-(lt - zmax)/De) for layers up
///               to ~1.6 De thick, so the lifting does not cure outside the contour at the top;
///   a_edge = 0.25 in the band the middle leaves short (sub-blocks 2, 4): room for the steep rise;
///   a_in = 0.05 inside the middle area (sub-blocks 3, 6): the ACES ripple's size.
/// With compensation the middle area's ACES vectors are cut into short pieces whose speeds follow
/// the compensated target Etar - E_t (Eq. 22) instead of Etar.
/// Linear edges are planned as rows of constant line density parallel to the edge, i.e. laser
/// vectors at power P and speed P / lambda. A corner between two edge blocks takes its dots on
/// the lines of those edges' rows, one dot pitch apart from the block's end through the corner
/// block, and runs each as a piece of its row (the row's line continued at the piece's own line
/// density), so the corner adds no scan lines: on four 0.3 mm pillars a grid of corner dots made
/// 750 jumps and 3.35x ACES's build time, the rows continued 604 and 2.48x. The rows run around
/// each contour, offset after offset, as ACES's border loops do. A corner without an edge block on
/// both sides (a short edge) keeps a dot grid around its vertex: laser points of given energy.
///
/// Exposure maps, own and transmitted, come from the exposure model (exposure::ExposureModel::
/// layerMap at the depth of the receiving layer's top). Units: mm, mW, mJ, dose mJ/mm^2.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/polygons.h"
#include "vpsim/kernel/fitted_beam.h"
#include "vpsim/plan/aces/aces.h"

namespace vpsim::optimise {

struct DfbtpParameters {
    /// Beam and process for the ACES middle area; criticalDose in delivered units (Ec divided by
    /// the beam efficiency), as for a stand-alone ACES plan. `edge` is ignored (5% rule).
    plan::AcesParameters aces;
    double gridPitch = 0.01;  ///< mm, planning grid (exposure maps, evaluation points)
    /// mm, corner dot and edge row spacing. Each edge row (with its corner pieces) is a scan line
    /// on the machine: at 20 um DFBTP took 4.9x ACES's build time on laser-overhang, 2.2x at 40 um
    /// (1.9x with the corner dots on the rows' lines).
    double dotPitch = 0.04;
    double liftOutside = 0.15, liftEdge = 0.25, liftInside = 0.05;  ///< a_i (see file comment)
    bool compensate = true;  ///< subtract the exposure transmitted from the layers above
    /// Target Etar on the region grown by targetWallShift() instead of the region itself, so that
    /// the cured wall (not the half-exposure edge) lies on the contour on average over the
    /// layer's depth; jobs with `edge: cure-at-contour` set it. Off: the seed's target map.
    bool wallOnContour = false;
};

/// Outward growth (mm) of the target region that puts the cured wall on the contour on average
/// over the layer's depth, for a plan that reproduces the target map's blurred step and
/// compensates print-through: the continuous-field limit of plan::acesContourDistance() with the
/// wall level Ec/Etar exp(d/De3D) and no print-through factor. Etar in `aces`'s dose units.
double targetWallShift(const plan::AcesParameters& aces, double targetDose);

/// Per-layer record of a DFBTP (or any top-down) plan.
struct LayerCompensation {
    double uncompensableArea = 0;  ///< mm^2 where the transmitted exposure exceeds the target
                                   ///< by more than 5% Etar (cannot be taken back by scanning)
    double uncompensableMax = 0;   ///< largest excess / Etar
    double curingOutsideArea = 0;  ///< mm^2 outside the region where the transmitted surface
                                   ///< exposure alone reaches Ec
    int edgeBlocks = 0, cornerBlocks = 0, cornerDots = 0;
    bool compensated = false;  ///< the layers above send more than 1% Etar into the region
};

struct DfbtpResult {
    plan::ScanPlan plan;
    std::vector<LayerCompensation> layers;  ///< same order as plan.layers (bottom first)
    double targetDose = 0;                  ///< Etar at the surface (mJ/mm^2, after efficiency)
};

/// Plans every layer (regions bottom first; tops[k] is layer k's top z, mm). The exposure maps
/// come from `model` (its grid must cover the regions plus Reff; the tabulated kernel works
/// too) or, when null, from a fitted-kernel engine on planningGrid(). The beam's numbers size the
/// features and the QP kernels.
/// @throw InputError for impossible parameters (as designAces) or mismatched sizes
DfbtpResult planDfbtp(const std::vector<geometry::PolygonSet>& regions,
                      const std::vector<double>& tops, const DfbtpParameters& parameters,
                      const kernel::FittedBeam& beam, exposure::ExposureModel* model = nullptr);

/// The exposure the layers above send into the top of layer k (Eq. 21) through the model:
/// sum over j > k of layerMap(deposit_j, (j - k) lt), over the layers whose transmission
/// exp(-(j - k) lt / De3D) exceeds 1e-4. `deposits` are bottom first.
exposure::SurfaceGrid transmittedExposure(exposure::ExposureModel& model,
                                          const std::vector<exposure::SurfaceGrid>& deposits, int k,
                                          double attenuationLength);

/// The planning grid covering every region plus a margin of Reff + 2 W.
exposure::ExposureGrid planningGrid(const std::vector<geometry::PolygonSet>& regions,
                                    double beamRadius, double pitch);

}  // namespace vpsim::optimise
