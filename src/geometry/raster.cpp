#include "vpsim/geometry/raster.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim::geometry {

RasterGrid RasterGrid::covering(const glm::dvec2& lo, const glm::dvec2& hi, double pitch,
                                int marginPixels) {
    if (!(pitch > 0.0) || !std::isfinite(pitch)) throw InputError("pixel pitch must be positive");
    RasterGrid grid;
    grid.pitch = pitch;
    if (!(lo.x <= hi.x && lo.y <= hi.y)) {  // empty region: a small blank grid
        grid.width = grid.height = 2 * marginPixels + 1;
        grid.origin = glm::dvec2(-marginPixels * pitch);
        return grid;
    }
    const glm::dvec2 first = glm::floor(lo / pitch) - double(marginPixels);
    const glm::dvec2 last = glm::ceil(hi / pitch) + double(marginPixels);
    const double pixels = (last.x - first.x) * (last.y - first.y);
    if (pixels > double(1u << 31)) {
        throw ResourceError("a raster of " + formatQuantity(pixels) + " pixels at pitch " +
                            formatQuantity(pitch) +
                            " mm is too large (limit 2^31): use a coarser pitch");
    }
    grid.origin = first * pitch;
    grid.width = int(last.x - first.x);
    grid.height = int(last.y - first.y);
    return grid;
}

std::vector<uint8_t> rasterizeBinary(const PolygonSet& region, const RasterGrid& grid) {
    return rasterizeBinary(region, grid, 0, 0, grid.width, grid.height);
}

std::vector<uint8_t> rasterizeBinary(const PolygonSet& region, const RasterGrid& grid, int x0,
                                     int y0, int width, int height) {
    std::vector<uint8_t> mask(size_t(width) * size_t(height), 0);
    // Crossings of each contour edge with the rows' centre lines (half-open in y: an edge counts
    // at row centre yc when min(y) <= yc < max(y), so shared vertices are counted once).
    std::vector<std::vector<double>> rows(static_cast<size_t>(height));
    for (const auto& contour : region.contours()) {
        for (size_t e = 0, n = contour.size(); e < n; ++e) {
            const glm::dvec2 a = (contour[e] - grid.origin) / grid.pitch - 0.5;
            const glm::dvec2 b = (contour[(e + 1) % n] - grid.origin) / grid.pitch - 0.5;
            if (a.y == b.y) continue;
            const int jLo = std::max(y0, int(std::ceil(std::min(a.y, b.y))));
            const int jHi = std::min(y0 + height - 1, int(std::ceil(std::max(a.y, b.y))) - 1);
            for (int j = jLo; j <= jHi; ++j)
                rows[size_t(j - y0)].push_back(a.x + (j - a.y) * (b.x - a.x) / (b.y - a.y));
        }
    }
    for (int j = 0; j < height; ++j) {
        auto& xs = rows[size_t(j)];
        std::sort(xs.begin(), xs.end());
        for (size_t k = 0; k + 1 < xs.size(); k += 2) {  // clean region: even-odd pairs
            const int iLo = std::max(x0, int(std::ceil(xs[k])));
            const int iHi = std::min(x0 + width - 1, int(std::ceil(xs[k + 1])) - 1);
            for (int i = iLo; i <= iHi; ++i) mask[size_t(j) * width + (i - x0)] = 1;
        }
    }
    return mask;
}

namespace {

/// Accumulates exact signed coverage: for an edge piece inside one pixel cell with vertical extent
/// dy and mean x offset f in the cell, the cell gets dy (1 - f) and every cell to its right dy.
/// Stored as a difference array (acc[i] and acc[i+1]) and prefix-summed per row afterwards.
class CoverageAccumulator {
public:
    CoverageAccumulator(int width, int height)
        : mWidth(width), mHeight(height), mAcc(size_t(width + 1) * height, 0.0) {}

    /// Edge from a to b in pixel units (grid origin at 0, one pixel = 1).
    void addEdge(glm::dvec2 a, glm::dvec2 b) {
        if (a.y == b.y) return;
        const double yLo = std::max(0.0, std::min(a.y, b.y)),
                     yHi = std::min(double(mHeight), std::max(a.y, b.y));
        if (yLo >= yHi) return;
        const double slope = (b.x - a.x) / (b.y - a.y);
        auto xAt = [&](double y) { return a.x + (y - a.y) * slope; };
        const bool up = b.y > a.y;
        for (int row = int(std::floor(yLo)); row < mHeight && row < yHi; ++row) {
            const double y0 = std::max(yLo, double(row)), y1 = std::min(yHi, double(row + 1));
            if (y0 >= y1) continue;
            // Traverse in the edge's own direction so dy carries its sign.
            const double ys = up ? y0 : y1, ye = up ? y1 : y0;
            addRowPiece(row, xAt(ys), ys, xAt(ye), ye);
        }
    }

    std::vector<double> coverage() const {
        std::vector<double> out(size_t(mWidth) * mHeight);
        for (int j = 0; j < mHeight; ++j) {
            double sum = 0.0;
            const double* acc = &mAcc[size_t(j) * (mWidth + 1)];
            for (int i = 0; i < mWidth; ++i) {
                sum += acc[i];
                // Counter-clockwise outers make the accumulated signed area negative.
                out[size_t(j) * mWidth + i] = std::clamp(-sum, 0.0, 1.0);
            }
        }
        return out;
    }

private:
    /// Splits a piece within one row at integer x and adds each cell's part.
    void addRowPiece(int row, double xa, double ya, double xb, double yb) {
        if (xa != xb) {
            const double lo = std::max(0.0, std::ceil(std::min(xa, xb)));
            const double hi = std::min(double(mWidth), std::floor(std::max(xa, xb)));
            const double step = xb > xa ? 1.0 : -1.0;
            double x = xb > xa ? lo : hi;
            for (; xb > xa ? x <= hi : x >= lo; x += step) {
                if ((x - xa) * step <= 0.0 || (xb - x) * step <= 0.0)
                    continue;  // not strictly inside
                const double y = ya + (x - xa) * (yb - ya) / (xb - xa);
                addCellPiece(row, xa, ya, x, y);
                xa = x;
                ya = y;
            }
        }
        addCellPiece(row, xa, ya, xb, yb);
    }

    void addCellPiece(int row, double xa, double ya, double xb, double yb) {
        const double dy = yb - ya, xm = 0.5 * (xa + xb);
        if (dy == 0.0 || xm >= mWidth) return;  // right of the grid: affects no pixel
        double* acc = &mAcc[size_t(row) * (mWidth + 1)];
        if (xm <= 0.0) {  // left of the grid: covers the whole row to the right
            acc[0] += dy;
            return;
        }
        const int col = std::min(mWidth - 1, int(std::floor(xm)));
        const double f = xm - col;
        acc[col] += dy * (1.0 - f);
        acc[col + 1] += dy * f;
    }

    int mWidth, mHeight;
    std::vector<double> mAcc;
};

double segmentDistance(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b) {
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

}  // namespace

std::vector<double> rasterizeCoverage(const PolygonSet& region, const RasterGrid& grid) {
    CoverageAccumulator acc(grid.width, grid.height);
    for (const auto& contour : region.contours()) {
        for (size_t e = 0, n = contour.size(); e < n; ++e) {
            acc.addEdge((contour[e] - grid.origin) / grid.pitch,
                        (contour[(e + 1) % n] - grid.origin) / grid.pitch);
        }
    }
    return acc.coverage();
}

TargetMap makeTargetMap(const PolygonSet& region, const RasterGrid& grid, double maxDistance) {
    if (!(maxDistance > 0.0)) throw InputError("target map distance limit must be positive");
    TargetMap map;
    map.grid = grid;
    map.maxDistance = maxDistance;
    const std::vector<double> coverage = rasterizeCoverage(region, grid);
    map.coverage.assign(coverage.begin(), coverage.end());
    map.signedDistance.assign(grid.pixelCount(), float(maxDistance));
    std::vector<double> distance(grid.pixelCount(), maxDistance);
    // Each edge, cut into pieces about maxDistance long, updates the pixels within maxDistance
    // of its bounding box: exact nearest-edge distance inside the band.
    const double pieceLength = std::max(maxDistance, 4.0 * grid.pitch);
    for (const auto& contour : region.contours()) {
        for (size_t e = 0, n = contour.size(); e < n; ++e) {
            const glm::dvec2 a = contour[e], b = contour[(e + 1) % n];
            const int pieces = std::max(1, int(std::ceil(glm::length(b - a) / pieceLength)));
            for (int s = 0; s < pieces; ++s) {
                const glm::dvec2 p = a + (b - a) * (double(s) / pieces),
                                 q = a + (b - a) * (double(s + 1) / pieces);
                const glm::dvec2 lo =
                    (glm::min(p, q) - maxDistance - grid.origin) / grid.pitch - 0.5;
                const glm::dvec2 hi =
                    (glm::max(p, q) + maxDistance - grid.origin) / grid.pitch - 0.5;
                const int i0 = std::max(0, int(std::ceil(lo.x))),
                          i1 = std::min(grid.width - 1, int(std::floor(hi.x)));
                const int j0 = std::max(0, int(std::ceil(lo.y))),
                          j1 = std::min(grid.height - 1, int(std::floor(hi.y)));
                for (int j = j0; j <= j1; ++j) {
                    for (int i = i0; i <= i1; ++i) {
                        double& d = distance[size_t(j) * grid.width + i];
                        d = std::min(d, segmentDistance(grid.pixelCentre(i, j), p, q));
                    }
                }
            }
        }
    }
    const std::vector<uint8_t> inside = rasterizeBinary(region, grid);
    for (size_t k = 0; k < distance.size(); ++k)
        map.signedDistance[k] = float(inside[k] ? -distance[k] : distance[k]);
    return map;
}

std::vector<uint8_t> toGreyImage(const std::vector<double>& values, const RasterGrid& grid) {
    std::vector<uint8_t> grey(values.size());
    for (size_t k = 0; k < values.size(); ++k)
        grey[k] = uint8_t(std::lround(255.0 * std::clamp(values[k], 0.0, 1.0)));
    return flipRows(grey, grid.width, grid.height);
}

}  // namespace vpsim::geometry
