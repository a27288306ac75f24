#pragma once
/// @file
/// Scan direction of a layer part (seed 002 Section 3). Hatching a region with parallel lines
/// along direction d at spacing h gives about P(d) / (2 h) scan vectors, where
/// P(d) = sum over edges e of |e x d| is the sum of the edges' projections onto the normal of d
/// (every line crosses the boundary twice per vector). Seed 002 therefore takes the direction of
/// minimum projection sum, and since P is a sum of |sin| terms, concave between edge directions,
/// its minimum lies on one of the edge directions (seed 002, after its ref. [11]): only those
/// need to be tried. Angles in radians from +x, in [0, pi).

#include <string>
#include <vector>

#include "vpsim/geometry/polygons.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::plan {

/// Job key `plan.direction`: "min-edge-projection" (default) | "longest-edge" | a fixed angle
/// such as "0 deg".
struct DirectionRule {
    enum class Kind { MinEdgeProjection, LongestEdge, Fixed };
    Kind kind = Kind::MinEdgeProjection;
    double angle = 0;  ///< rad, for Kind::Fixed
};

/// Parses a `plan.direction` value. @throw InputError naming `key` and `file` otherwise
DirectionRule parseDirectionRule(const std::string& text, const std::string& key = "plan.direction",
                                 const std::string& file = "");
/// The rule as the job would spell it ("min-edge-projection", "longest-edge", "30 deg").
std::string toString(const DirectionRule& rule);

/// P(direction): sum over all contour edges (outers and holes) of |e x d| (mm).
double edgeProjectionSum(const geometry::PolygonSet& region, double direction);

/// The scan direction (rad, [0, pi)) the rule picks for `region`; 0 for an empty region.
double scanDirection(const geometry::PolygonSet& region, const DirectionRule& rule);

/// Hatches each part of `region` (an outer contour with its holes) on its own, along the
/// direction `rule` picks for that part (seed 002 Fig. 4), with parallel lines at `spacing`
/// alternating line by line (plan/aces/aces.h hatchRegion); parts in the region's order.
/// @throw InputError for a non-positive spacing or speed
std::vector<LaserVector> hatchPartsByRule(const geometry::PolygonSet& region, double spacing,
                                          const DirectionRule& rule, double power, double speed);

}  // namespace vpsim::plan
