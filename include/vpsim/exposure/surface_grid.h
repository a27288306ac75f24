#pragma once
/// @file
/// A regular 2D grid in the build plane: the energy a layer's plan deposits at the resin surface
/// and, after the beam blur, that layer's exposure map (mJ/mm^2).

#include <cstddef>
#include <vector>

namespace vpsim::exposure {

struct SurfaceGrid {
    int nx = 0, ny = 0;
    double originX = 0, originY = 0;  ///< mm, corner of cell (0, 0) of the whole grid
    double pitch = 0;                 ///< mm, cell size in x and y
    std::vector<float> values;        ///< row-major, values[j * nx + i]; mJ/mm^2
    /// A tile's window of a larger grid holds that grid's cells from (firstI, firstJ) on; the
    /// origin stays the larger grid's, so positions are computed the same way in every tile.
    int firstI = 0, firstJ = 0;

    SurfaceGrid() = default;
    SurfaceGrid(int nx_, int ny_, double originX_, double originY_, double pitch_)
        : nx(nx_),
          ny(ny_),
          originX(originX_),
          originY(originY_),
          pitch(pitch_),
          values(size_t(nx_) * ny_, 0.0f) {}
    double centreX(int i) const { return originX + (firstI + i + 0.5) * pitch; }
    double centreY(int j) const { return originY + (firstJ + j + 0.5) * pitch; }
    float& at(int i, int j) { return values[size_t(j) * nx + i]; }
    float at(int i, int j) const { return values[size_t(j) * nx + i]; }
    /// Sum of values x cell area: the energy on the grid in mJ.
    double totalEnergy() const;
};

}  // namespace vpsim::exposure
