#pragma once
/// @file
/// ACES hatching of a layer region (seed 000 Section III-B1 and Appendices A-C): parallel scan
/// lines along the region's longest edge, at the hatch spacing that keeps the exposure ripple
/// within a homogeneity target, at the speed that gives the target exposure, inside the contour
/// offset inward by Roff.
///
/// The seed gives the hatch spacing (Eq. 15) and Roff (Eq. 13) as fits with coefficients that
/// were lost in extraction; vpsim computes both numerically from the same definitions instead:
/// - ripple: the exposure of infinitely many lines at spacing rh W (rh = hs/W) is periodic,
///   E(y) = sqrt(2/pi) P/(W V) sum_l exp(-2 (y/W - l rh)^2) (Eq. C.7); its relative standard
///   deviation over one period must not exceed Srlt;
/// - Roff: for a half-plane of lines the exposure falls from the plateau Ep to 5% Ep at a
///   distance y5 beyond the last line (App. A); Roff = y5, so the 5% Ep edge lies on the contour.
/// The App. A and App. B fits do exist in the seed (tests/data/reference/seed000_slurry_case.json
/// holds a = [0.81701, 0.50713, -0.15195] for Roff/W0 and c1..c4 for Srlt(rh)); vpsim keeps the
/// numerical derivation because it is exact for any edge fraction (the cure-at-contour rule needs
/// other fractions than 5%), and a test compares it with the seed's Roff fit.
///
/// Contour rule (AcesEdge::CureAtContour): the exposure falls by exp(-d/De3D) with depth d, so
/// the cured wall of a layer is not vertical: at the top of the layer it lies where the surface
/// exposure is Ec, at the bottom where it is Ec exp(lt/De3D) (less the print-through of the layers
/// above). vpsim places the outermost line so that the wall position averaged over the layer's
/// depth lies on the contour and reports the half peak-to-peak scallop of the wall. Alone
/// (acesContourDistance) the rule assumes identical layers above; the planner "aces" designs the
/// layers top down and uses the stack-aware rule (acesStackContourOffset), which counts what the
/// real layers above send to this layer's wall (little above a taper, much under an overhang)
/// and the wall's slope through the layer.
/// Border scans: `borderCount` loops along the contour (the first at the edge offset, the next
/// ones one hatch spacing further in each) so curved and slanted walls follow the contour; the
/// hatch field fills what is inside the last loop. Small features (parts of the region that the
/// inward offset removes: strips narrower than two edge offsets, spikes, specks) get a single
/// centred line or a spot, so every layer region is exposed; a layer that still gets nothing is
/// logged as a warning.
/// Units: mm, mW, mm/s, dose mJ/mm^2.

#include <optional>
#include <vector>

#include "vpsim/geometry/polygons.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::plan {

/// Where the outermost scan line sits relative to the contour.
enum class AcesEdge {
    SeedFivePercent,  ///< seed 000 App. A: the 5% Ep edge on the contour (edges left to DFBTP)
    CureAtContour,    ///< the surface exposure at the contour equals Ec (a stand-alone ACES plan)
};

struct AcesParameters {
    double beamRadius = 0.05;         ///< We3D (mm)
    double attenuationLength = 0.12;  ///< De3D (mm)
    double depthOfMaximum = 0.0;      ///< zmax (mm), depth of the sub-surface intensity maximum
    double criticalDose = 0.1;        ///< Ec (mJ/mm^2)
    double layerThickness = 0.05;     ///< lt (mm)
    double laserPower = 10.0;         ///< P (mW)
    double homogeneity = 0.01;        ///< Srlt: allowed relative standard deviation of the exposure
    AcesEdge edge = AcesEdge::SeedFivePercent;
    std::optional<double> direction;  ///< scan direction (rad from +x); default: longest edge
    int borderCount = 1;              ///< border (contour) scan loops, >= 0
    /// Inward offset of the first border loop (mm); default: the edge rule's offset.
    std::optional<double> borderOffset;
    /// Contour rule: count the print-through of identical layers above (steady state of a
    /// vertical wall, factor 1/(1 - exp(-lt/De3D))); false for a single or top layer.
    bool steadyPrintThrough = true;
};

/// The numbers of an ACES design for one region.
struct AcesDesign {
    double targetDose = 0;    ///< Etar (mJ/mm^2), Eq. 14
    double hatchSpacing = 0;  ///< hs (mm), fitted to a whole number of spaces across the region
    double speed = 0;         ///< Vs (mm/s), Eq. C.9
    double edgeOffset = 0;    ///< inward offset of the line field from the contour (mm)
    double direction = 0;     ///< rad from +x
    double ripple = 0;        ///< relative standard deviation of the exposure at hs (Eq. C.7)
    double beamRadius = 0;    ///< We3D (mm), for the small-feature lines and spots
    int borderCount = 0;      ///< border loops (see AcesParameters::borderCount)
    /// Surface exposure at the contour relative to Etar (0.05 for the seed rule).
    double wallLevel = 0;
    /// Half peak-to-peak excursion of the cured wall over the layer's depth (mm); 0 for the seed
    /// rule, which does not put the wall on the contour.
    double scallop = 0;
};

/// What planAcesLayer() did beyond the hatch, for reports.
struct AcesLayerInfo {
    int smallFeatureLines = 0;  ///< small features planned as a single line
    int smallFeatureSpots = 0;  ///< small features planned as a spot
    bool unexposed = false;     ///< the region got no exposure at all (logged as a warning)
};

/// Etar = Ec / exp(-(lt - zmax)/De3D) (Eq. 14): the bottom of the layer still reaches Ec.
double acesTargetDose(double criticalDose, double layerThickness, double depthOfMaximum,
                      double attenuationLength);
/// Relative standard deviation of the infinite-field exposure for hatch ratio rh = hs/W.
double acesRipple(double hatchRatio);
/// Largest hatch ratio whose ripple is at most `homogeneity`. @throw InputError if homogeneity <= 0
double acesHatchRatio(double homogeneity);
/// Distance beyond the last line (in units of W) where a half-field's exposure is `fraction` of
/// its plateau, for hatch ratio rh.
double acesEdgeDistance(double hatchRatio, double fraction);
/// Contour rule: distance (units of W) from the outermost line to the contour such that the cured
/// wall, averaged over the layer's depth, lies on the contour. `surfaceFraction` is Ec/Etar,
/// `depthRatio` lt/De3D, `printThrough` the factor on the layer's own exposure from the layers
/// above (1 for none). Writes the half peak-to-peak wall excursion (units of W) to `scallop`.
double acesContourDistance(double hatchRatio, double surfaceFraction, double depthRatio,
                           double printThrough, double* scallop = nullptr);
/// A layer beside the planned one, as the stack-aware contour rule sees it.
struct AcesNeighbour {
    const geometry::PolygonSet* region = nullptr;
    double distance = 0;    ///< |z| between the two layers' slicing planes (mm), > 0
    double edgeOffset = 0;  ///< its design's edge offset (mm); used for the layers above only
};

/// What the stack-aware contour rule knows about the layers around the planned one (ACES plans
/// top down, so the layers above are designed already).
struct AcesStack {
    std::vector<AcesNeighbour> above;    ///< layers above, nearest first, each already designed
    std::optional<AcesNeighbour> below;  ///< the layer below (the wall's slope through the layer)
};

/// Stack-aware contour rule (AcesEdge::CureAtContour with the layers around known): the edge
/// offset (mm) that puts the cured wall on the model's wall on average over the contour and the
/// layer's depth. At sample points along the contour (outward normal n) the wall at depth d lies
/// at the outward distance t where the own half-field profile plus what each layer above sends
/// (its half-field profile at the point's signed distance from its contour and its edge offset,
/// times exp(-dz/De3D)) reaches (Ec/Etar) exp(d/De3D); the model's wall at that depth moves
/// linearly from the slicing plane toward the neighbours' contours (a taper), or stays put where
/// a neighbour's contour is more than 1.75 layer spacings away (a step, not a slope). The offset
/// is chosen in [0, 3 W] so that the mean of (t - model wall) is zero. Writes the half
/// peak-to-peak excursion of the contour-mean wall over the depth (mm) to `scallop`.
double acesStackContourOffset(const AcesParameters& parameters, const geometry::PolygonSet& region,
                              double hatchRatio, double targetDose, const AcesStack& stack,
                              double* scallop = nullptr);

/// Direction (rad from +x, in [0, pi)) of the region's longest contour edge.
double longestEdgeDirection(const geometry::PolygonSet& region);

/// With `stack`, the cure-at-contour rule (without a border_offset) is the stack-aware one
/// (acesStackContourOffset) and steadyPrintThrough is ignored.
/// @throw InputError for non-positive parameters or an empty region
AcesDesign designAces(const AcesParameters& parameters, const geometry::PolygonSet& region,
                      const AcesStack* stack = nullptr);

/// Parallel scan vectors at `spacing` along `direction`, clipped to the region (scan-line
/// intersection with the contours, even-odd), alternating in direction line by line. With
/// `clip`, the lines' positions come from `region` and their ends from `clip`.
std::vector<LaserVector> hatchRegion(const geometry::PolygonSet& region, double spacing,
                                     double direction, double power, double speed,
                                     const geometry::PolygonSet* clip = nullptr);

/// Closed scan loops along every contour of `region` (one vector per contour edge).
std::vector<LaserVector> contourLoops(const geometry::PolygonSet& region, double power,
                                      double speed);

/// The ACES plan of one layer: design.borderCount border loops from design.edgeOffset inward,
/// the hatch inside them, and a line or a spot for each small feature. Logs a warning when the
/// non-empty region gets no exposure.
LayerPlan planAcesLayer(const geometry::PolygonSet& region, const AcesDesign& design,
                        double laserPower, double z, AcesLayerInfo* info = nullptr);

/// Parts of `region` the plan's line field misses: the region minus the opening of the region
/// by `edgeOffset` grown by half a beam radius (so the rounded-off tips of ordinary convex
/// corners do not count), keeping pieces larger than (W/10)^2.
geometry::PolygonSet smallFeatures(const geometry::PolygonSet& region, double edgeOffset,
                                   double beamRadius);

}  // namespace vpsim::plan

namespace vpsim {
class ConfigNode;
}

namespace vpsim::plan {}  // namespace vpsim::plan
