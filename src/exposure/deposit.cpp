#include "vpsim/exposure/deposit.h"

#include <algorithm>
#include <cmath>

namespace vpsim::exposure {
namespace {

/// Adds energy-per-length `q` (mJ/mm) along the segment, split by the exact path length inside
/// each cell (a grid walk in the style of Amanatides & Woo).
void depositSegment(SurfaceGrid& grid, double x0, double y0, double x1, double y1, double q) {
    double length = std::hypot(x1 - x0, y1 - y0);
    if (length <= 0 || q <= 0) return;
    // Cut the segment at every vertical and horizontal cell boundary it crosses.
    std::vector<double> cuts{0.0, 1.0};
    auto addCuts = [&](double a0, double a1, double origin) {
        if (a0 == a1) return;
        double lo = std::min(a0, a1), hi = std::max(a0, a1);
        for (double k = std::ceil((lo - origin) / grid.pitch); origin + k * grid.pitch < hi; k += 1.0) {
            double t = (origin + k * grid.pitch - a0) / (a1 - a0);
            if (t > 0 && t < 1) cuts.push_back(t);
        }
    };
    addCuts(x0, x1, grid.originX);
    addCuts(y0, y1, grid.originY);
    std::sort(cuts.begin(), cuts.end());
    const double perArea = q / (grid.pitch * grid.pitch);
    for (size_t c = 0; c + 1 < cuts.size(); ++c) {
        double t0 = cuts[c], t1 = cuts[c + 1];
        if (t1 <= t0) continue;
        double tm = 0.5 * (t0 + t1);
        int i = int(std::floor((x0 + tm * (x1 - x0) - grid.originX) / grid.pitch));
        int j = int(std::floor((y0 + tm * (y1 - y0) - grid.originY) / grid.pitch));
        if (i < 0 || j < 0 || i >= grid.nx || j >= grid.ny) continue;
        grid.at(i, j) += float(perArea * (t1 - t0) * length);
    }
}

void depositPoint(SurfaceGrid& grid, double x, double y, double energy) {
    double fx = (x - grid.originX) / grid.pitch - 0.5, fy = (y - grid.originY) / grid.pitch - 0.5;
    int i = int(std::floor(fx)), j = int(std::floor(fy));
    double ax = fx - i, ay = fy - j;
    const double perArea = energy / (grid.pitch * grid.pitch);
    const double weights[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
    const int di[4] = {0, 1, 0, 1}, dj[4] = {0, 0, 1, 1};
    for (int k = 0; k < 4; ++k) {
        int ii = i + di[k], jj = j + dj[k];
        if (ii >= 0 && jj >= 0 && ii < grid.nx && jj < grid.ny) grid.at(ii, jj) += float(perArea * weights[k]);
    }
}

/// Overlap lengths of the interval [a, a + size) with the grid cells along one axis.
std::vector<std::pair<int, double>> overlaps(double a, double size, double origin, double pitch, int count) {
    std::vector<std::pair<int, double>> result;
    int first = int(std::floor((a - origin) / pitch)), last = int(std::floor((a + size - origin) / pitch));
    for (int c = std::max(first, 0); c <= std::min(last, count - 1); ++c) {
        double lo = std::max(a, origin + c * pitch), hi = std::min(a + size, origin + (c + 1) * pitch);
        if (hi > lo) result.emplace_back(c, hi - lo);
    }
    return result;
}

void depositMask(SurfaceGrid& grid, const plan::MaskImage& mask) {
    const double cellArea = grid.pitch * grid.pitch;
    for (int v = 0; v < mask.height; ++v) {
        auto rows = overlaps(mask.originY + v * mask.pixelPitch, mask.pixelPitch, grid.originY, grid.pitch, grid.ny);
        for (int u = 0; u < mask.width; ++u) {
            float dose = mask.dose[size_t(v) * mask.width + u];
            if (dose <= 0) continue;
            auto cols = overlaps(mask.originX + u * mask.pixelPitch, mask.pixelPitch, grid.originX, grid.pitch, grid.nx);
            for (const auto& [j, ly] : rows)
                for (const auto& [i, lx] : cols) grid.at(i, j) += float(dose * lx * ly / cellArea);
        }
    }
}

} // namespace

void depositLayer(const plan::LayerPlan& layer, SurfaceGrid& grid) {
    for (const auto& v : layer.vectors) depositSegment(grid, v.x0, v.y0, v.x1, v.y1, v.power / v.speed);
    for (const auto& p : layer.points) depositPoint(grid, p.x, p.y, p.energy);
    for (const auto& m : layer.masks) depositMask(grid, m);
}

} // namespace vpsim::exposure
