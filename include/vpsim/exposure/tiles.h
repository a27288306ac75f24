#pragma once
/// @file
/// x-y tiles of the exposure grid, so that a run's memory depends on the tile, not the part:
/// each tile owns a rectangle of cells (its core) and is computed on the core plus a halo as
/// wide as the kernel's reach and what the consumers look at beside a cell (the mesher's one
/// cell), so every core cell gets the exposure the whole grid gives it, bit for bit.

#include <vector>

#include "vpsim/exposure/exposure_model.h"

namespace vpsim::exposure {

struct Tile {
    int index = 0;      ///< row-major over the tiles (x fastest); the fixed order of merges
    CellWindow core;    ///< the cells this tile owns; the cores cover the grid once
    CellWindow window;  ///< core plus the halo, clipped to the grid: the cells computed
};

/// Tiles of at most `tileCells` x `tileCells` core cells (one tile of the whole grid when
/// tileCells <= 0 or the grid is smaller), cores of equal size but the last in each direction.
std::vector<Tile> tileLayout(const ExposureGrid& grid, int tileCells, int halo);

}  // namespace vpsim::exposure
