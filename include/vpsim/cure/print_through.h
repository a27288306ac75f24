#pragma once
/// @file
/// Print-through along Z in layered exposure (DLP masks or laser layers), seed 001 Eq. 4 and
/// seed 000 Eq. 21: each layer's exposure is applied at the resin surface (the top of the layer
/// being built) and reaches the already built layers below attenuated by Beer-Lambert,
///     Delta d_j = d_j exp(-mu Delta z_j)         (seed 001 Eq. 4, mu = 1/Dp),
/// so a point receives the sum over its own layer and every later layer.
///
/// Layer convention: layer i (0 = first printed, at the bottom) occupies heights
/// [i Le, (i+1) Le]; its exposure d_i is the dose at its top surface (i+1) Le. A point at
/// height h receives d_j exp(-((j+1) Le - h) / Dp) from every layer j with (j+1) Le >= h.
/// Units: dose mJ/mm^2, lengths mm.

#include <vector>

namespace vpsim::cure {

/// Seed 001 Eq. 4: dose (mJ/mm^2) that a surface dose reaches `distance` (mm, >= 0) below the
/// surface: d exp(-distance / Dp).
double printThroughDose(double surfaceDose, double distance, double penetrationDepth);

/// Accumulated dose at the top surface of every layer after the whole stack is exposed:
///     D_i = sum_{j >= i} d_j exp(-(j - i) Le / Dp),
/// computed by the recursion D_{n-1} = d_{n-1}, D_i = d_i + exp(-Le/Dp) D_{i+1} (O(n)).
/// @param layerDoses d_i, mJ/mm^2 (>= 0), bottom layer first
/// @param layerThickness Le, mm (> 0) @param penetrationDepth Dp, mm (> 0)
/// @return D_i, mJ/mm^2, one per layer
/// @throw InputError on a negative or non-finite dose or a non-positive length
std::vector<double> accumulatedLayerDoses(const std::vector<double>& layerDoses,
                                          double layerThickness, double penetrationDepth);

/// Accumulated dose at height h (mm) by the direct sum over the layers whose top is at or above
/// h (the reference for the recursion, and doses inside layers). Heights below 0 are allowed
/// (resin below a down-facing surface). O(n).
/// @throw InputError as accumulatedLayerDoses
double accumulatedDoseAtHeight(const std::vector<double>& layerDoses, double layerThickness,
                               double penetrationDepth, double height);

/// Accumulated dose at the bottom surface of layer i, i.e. exp(-Le/Dp) D_i: the least-exposed
/// point of layer i, and the dose a down-facing surface under layer i sees.
std::vector<double> accumulatedBottomDoses(const std::vector<double>& layerDoses,
                                           double layerThickness, double penetrationDepth);

}  // namespace vpsim::cure
