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
};

/// The numbers of an ACES design for one region.
struct AcesDesign {
    double targetDose = 0;    ///< Etar (mJ/mm^2), Eq. 14
    double hatchSpacing = 0;  ///< hs (mm), fitted to a whole number of spaces across the region
    double speed = 0;         ///< Vs (mm/s), Eq. C.9
    double edgeOffset = 0;    ///< inward offset of the line field from the contour (mm)
    double direction = 0;     ///< rad from +x
    double ripple = 0;        ///< relative standard deviation of the exposure at hs (Eq. C.7)
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
/// Direction (rad from +x, in [0, pi)) of the region's longest contour edge.
double longestEdgeDirection(const geometry::PolygonSet& region);

/// @throw InputError for non-positive parameters or an empty region
AcesDesign designAces(const AcesParameters& parameters, const geometry::PolygonSet& region);

/// Parallel scan vectors at `spacing` along `direction`, clipped to the region (scan-line
/// intersection with the contours, even-odd), alternating in direction line by line.
std::vector<LaserVector> hatchRegion(const geometry::PolygonSet& region, double spacing,
                                     double direction, double power, double speed);

/// The ACES plan of one layer: the region offset inward by design.edgeOffset, hatched.
LayerPlan planAcesLayer(const geometry::PolygonSet& region, const AcesDesign& design,
                        double laserPower, double z);

}  // namespace vpsim::plan
