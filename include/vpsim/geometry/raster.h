#pragma once
/// @file
/// Pixel masks of layer regions for DLP masks, planners and exposure grids.
///
/// Grid convention: pixel (i, j) covers x in [origin.x + i p, origin.x + (i+1) p] and
/// y in [origin.y + j p, origin.y + (j+1) p] (p = pitch, mm); images are stored row-major with
/// index j * width + i and j growing with +y (row 0 at the bottom). flipRows() turns such a
/// raster into top-to-bottom image order for PNG writing.

#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "vpsim/geometry/polygons.h"

namespace vpsim::geometry {

/// A regular pixel grid in the layer plane.
struct RasterGrid {
    glm::dvec2 origin{0.0, 0.0};  ///< lower-left corner of pixel (0, 0) (mm)
    double pitch = 0.01;          ///< pixel size (mm)
    int width = 0, height = 0;    ///< pixels along x and y

    size_t pixelCount() const { return size_t(width) * size_t(height); }
    glm::dvec2 pixelCentre(int i, int j) const {
        return origin + pitch * glm::dvec2(i + 0.5, j + 0.5);
    }
    /// The grid of the given pitch covering [lo, hi] plus `marginPixels` on each side, with its
    /// origin on a multiple of the pitch (so grids of different layers line up).
    /// @throw InputError on a non-positive pitch; ResourceError beyond 2^31 pixels
    static RasterGrid covering(const glm::dvec2& lo, const glm::dvec2& hi, double pitch,
                               int marginPixels = 2);
};

/// 1 where the pixel centre is inside the region (a centre exactly on an edge is resolved by a
/// consistent half-open rule), else 0.
std::vector<uint8_t> rasterizeBinary(const PolygonSet& region, const RasterGrid& grid);
/// The same for the pixels [x0, x0 + width) x [y0, y0 + height) of `grid` only (row-major,
/// width x height), computed in the whole grid's coordinates: a tile's pixels equal the whole
/// grid's bit for bit.
std::vector<uint8_t> rasterizeBinary(const PolygonSet& region, const RasterGrid& grid, int x0,
                                     int y0, int width, int height);

/// Exact fraction of each pixel covered by the region, in [0, 1]: the polygon-pixel intersection
/// area divided by p^2 (edges are clipped into pixel rows and columns and their signed areas
/// accumulated, as in exact-coverage font rasterisers). Sum * p^2 equals the area of the part of
/// the region inside the grid to rounding error.
std::vector<double> rasterizeCoverage(const PolygonSet& region, const RasterGrid& grid);

/// What planners need of one layer on a pixel grid.
struct TargetMap {
    RasterGrid grid;
    std::vector<float> coverage;        ///< exact area fraction per pixel, [0, 1]
    std::vector<float> signedDistance;  ///< distance from the pixel centre to the nearest contour
                                        ///< edge (mm), negative inside, clamped to +-maxDistance
    double maxDistance = 0.0;           ///< mm
};

/// Coverage plus exact signed distance to the contour within maxDistance (mm) of it.
/// Cost grows with (perimeter / pitch) x (maxDistance / pitch).
TargetMap makeTargetMap(const PolygonSet& region, const RasterGrid& grid, double maxDistance);

/// Converts values in [0, 1] to 8-bit grey (rounded) in top-to-bottom row order for writePngGrey.
std::vector<uint8_t> toGreyImage(const std::vector<double>& values, const RasterGrid& grid);
/// Reverses the row order of a row-major raster (bottom-up <-> top-down).
template <typename T>
std::vector<T> flipRows(const std::vector<T>& values, int width, int height) {
    std::vector<T> out(values.size());
    for (int j = 0; j < height; ++j) {
        std::copy(values.begin() + size_t(j) * width, values.begin() + size_t(j + 1) * width,
                  out.begin() + size_t(height - 1 - j) * width);
    }
    return out;
}

}  // namespace vpsim::geometry
