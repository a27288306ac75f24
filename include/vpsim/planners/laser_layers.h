#pragma once
/// @file
/// What the laser optimisers' planners (dfbtp, inverse) share around their algorithm: the layer
/// regions and tops they take, and the report of what print-through compensation could not take
/// back.

#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/planners/planner.h"

namespace vpsim::planners {

std::vector<geometry::PolygonSet> layerRegions(const PlannerInputs& inputs);
std::vector<double> layerTops(const plan::ScanPlan& empty);

/// The part at the shape objective's voxel slices (optimise/laser/inverse_shape.h): `n` per
/// layer of `plan`, slice 0 at the layer's top; the mesh sliced there, else each layer's region.
std::vector<geometry::PolygonSet> shapeSlices(const PlannerInputs& inputs,
                                              const plan::ScanPlan& plan, int n);

/// {"uncompensable_area_mm2", "uncompensable_max_excess_over_Etar",
///  "transmitted_cures_outside_area_mm2", "uncompensable_layers": [...]}
nlohmann::json compensationJson(const std::vector<optimise::LayerCompensation>& layers);

/// The planning-grid keys of the laser optimisers: dot_pitch (default `dotPitchDefault`),
/// grid_pitch, compensate.
KeyTable laserOptimiserKeyTable(const std::string& dotPitchDoc,
                                const char* dotPitchDefault = "20 um");

}  // namespace vpsim::planners
