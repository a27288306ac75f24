#pragma once
// Private: the non-zero columns of each row of a layer's deposit, which the tabulated engine's
// CPU gather and its shader dispatch use to skip the empty parts of a sparse scan.
#include <vector>

#include "vpsim/exposure/surface_grid.h"

namespace vpsim::exposure {

/// Non-zero columns [first, last] of a deposit row (first > last for an empty row).
struct RowExtent {
    int first, last;
};

/// Each row's non-zero columns (TBB-parallel over rows).
std::vector<RowExtent> rowExtents(const SurfaceGrid& grid);

}  // namespace vpsim::exposure
