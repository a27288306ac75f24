#pragma once
/// @file
/// DLP dose optimisation of a whole part: every pixel column of the voxelised layer stack is
/// optimised along Z (seed 001 assumes no light transfer between pixels), columns with the same
/// solid/void profile are solved once, and the doses come back as one image per layer.
/// Plain inputs (solid masks per layer, the cure law's K, gel point, Dp, the layer thickness), so
/// a planner wraps it in a few lines.

#include <cstdint>
#include <string>
#include <vector>

#include "vpsim/optimise/dlp/geometric.h"
#include "vpsim/optimise/dlp/pattern_search.h"

namespace vpsim::optimise {

/// Which column problem to solve.
enum class DlpObjective { ConversionL2, Geometric };

/// Parses "conversion-l2" / "geometric". @throw InputError otherwise
DlpObjective dlpObjectiveFromName(const std::string& name);
/// Parses "own-layer" / "run-bottom". @throw InputError otherwise
Bonding bondingFromName(const std::string& name);

/// A voxelised part: layers[k] is layer k's solid mask (width x height, row-major, non-zero =
/// part), layer 0 first (bottom).
struct DlpLayerStack {
    int width = 0, height = 0;
    std::vector<std::vector<uint8_t>> layers;
};

struct DlpPartOptions {
    DlpColumnProblem problem;  ///< resin, layer thickness, d_max, targets, bonding
    DlpObjective objective = DlpObjective::ConversionL2;
    DlpSearchOptions search;
    DlpGeometricOptions geometric;
};

struct DlpPartResult {
    int width = 0, height = 0;
    std::vector<std::vector<float>> dose;  ///< per layer, per pixel, mJ/mm^2
    size_t distinctColumns = 0;            ///< distinct solid/void profiles solved (non-empty)
    double maxGap = 0.0;                   ///< largest relative optimality gap of any column
    double meanGap = 0.0;                  ///< mean relative gap over distinct columns
    size_t openColumns = 0;                ///< columns whose search stopped with a gap > 1e-9
    double seconds = 0.0;                  ///< wall time of the optimisation
};

/// Optimises every column (in parallel over distinct profiles, TBB).
/// @throw InputError on inconsistent mask sizes or bad problem parameters
DlpPartResult optimiseDlpPart(const DlpLayerStack& part, const DlpPartOptions& options);

/// The solid profile (one byte per layer) of column (x, y).
std::vector<uint8_t> columnProfile(const DlpLayerStack& part, int x, int y);

/// Doses of column (x, y) of a result (mJ/mm^2 per layer).
std::vector<double> columnDoses(const DlpPartResult& result, int x, int y);

}  // namespace vpsim::optimise
