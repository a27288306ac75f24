#include "exposure/row_extents.h"

#include <tbb/parallel_for.h>

namespace vpsim::exposure {

std::vector<RowExtent> rowExtents(const SurfaceGrid& grid) {
    std::vector<RowExtent> extents(size_t(grid.ny));
    tbb::parallel_for(0, grid.ny, [&](int j) {
        const float* row = grid.values.data() + size_t(j) * grid.nx;
        int first = 0, last = grid.nx - 1;
        while (first < grid.nx && row[first] == 0.0f) ++first;
        while (last >= first && row[last] == 0.0f) --last;
        extents[size_t(j)] = {first, last};
    });
    return extents;
}

}  // namespace vpsim::exposure
