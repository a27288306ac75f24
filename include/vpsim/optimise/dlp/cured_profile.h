#pragma once
/// @file
/// Where a column's doses cure it, exactly (no sampling), and the caliper lengths of seed 001
/// Table 2 on that profile. Layer i spans [i Le, (i+1) Le] and receives the accumulated dose D_i
/// at its top (print-through, Eq. 4); inside it the dose is D_i exp(-((i+1) Le - h) / Dp), so its
/// cured part is [max(i Le, (i+1) Le - Dp ln(D_i / Ec)), (i+1) Le] when D_i >= Ec. Void layers
/// are included (their dose is the print-through of the layers above), so over-cure below a
/// down-facing surface appears as cured length in the void.
/// Units: mm, dose mJ/mm^2.

#include <utility>
#include <vector>

namespace vpsim::optimise {

/// Cured intervals [z0, z1] (mm, merged, ascending) of a column with per-layer doses `dose`.
/// @throw InputError on a negative dose or non-positive parameters
std::vector<std::pair<double, double>> curedIntervals(const std::vector<double>& dose,
                                                      double layerThickness,
                                                      double penetrationDepth, double criticalDose);

/// Cured length (mm) of `intervals` inside [zMin, zMax] (an overhang's thickness).
double curedLength(const std::vector<std::pair<double, double>>& intervals, double zMin,
                   double zMax);

/// Uncured length (mm) inside [zMin, zMax] (a hole's height).
double uncuredLength(const std::vector<std::pair<double, double>>& intervals, double zMin,
                     double zMax);

}  // namespace vpsim::optimise
