#include "vpsim/exposure/tiles.h"

#include <algorithm>

namespace vpsim::exposure {

std::vector<Tile> tileLayout(const ExposureGrid& grid, int tileCells, int halo) {
    const int size = tileCells > 0 ? tileCells : std::max(grid.nx, grid.ny);
    const int across = (grid.nx + size - 1) / size, down = (grid.ny + size - 1) / size;
    std::vector<Tile> tiles;
    for (int b = 0; b < down; ++b)
        for (int a = 0; a < across; ++a) {
            Tile t;
            t.index = int(tiles.size());
            t.core = {a * size, b * size, std::min(grid.nx, (a + 1) * size),
                      std::min(grid.ny, (b + 1) * size)};
            t.window = {std::max(0, t.core.i0 - halo), std::max(0, t.core.j0 - halo),
                        std::min(grid.nx, t.core.i1 + halo), std::min(grid.ny, t.core.j1 + halo)};
            tiles.push_back(t);
        }
    return tiles;
}

}  // namespace vpsim::exposure
