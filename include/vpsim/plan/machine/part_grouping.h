#pragma once
/// @file
/// Which layer part each vector and point of a layer plan belongs to. With the sliced region of
/// the layer, a part is one outer contour with its holes and an element belongs to the part that
/// contains its midpoint (else the nearest). Without it (a saved plan), elements closer than
/// `gap` (segment to segment) are joined, transitively. Units: mm.

#include <vector>

#include "vpsim/geometry/polygons.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::plan {

/// Per part, indices into layer.vectors and layer.points, each in plan order. Parts are numbered
/// as the region lists them, or by their first element in the plan.
struct PartGroups {
    std::vector<std::vector<int>> vectors, points;
};

PartGroups groupLayerParts(const LayerPlan& layer, double gap,
                           const geometry::PolygonSet* region = nullptr);

}  // namespace vpsim::plan
