#include "vpsim/exposure/deposit.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "exposure/avx2_clones.h"

namespace vpsim::exposure {
namespace {

/// Rows [jLo, jHi) of the grid: a band that one thread owns (indices of the grid's own cells).
struct Rows {
    int lo, hi;
};

// Positions are turned into cells of the whole grid (from its origin) and then shifted to the
// window's (firstI, firstJ), so a tile's cells get exactly the additions the whole grid's do.

void depositPoint(SurfaceGrid& grid, double x, double y, double energy, Rows rows) {
    double fx = (x - grid.originX) / grid.pitch - 0.5, fy = (y - grid.originY) / grid.pitch - 0.5;
    int i = int(std::floor(fx)), j = int(std::floor(fy));
    double ax = fx - i, ay = fy - j;
    i -= grid.firstI;
    j -= grid.firstJ;
    const double perArea = energy / (grid.pitch * grid.pitch);
    const double weights[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
    const int di[4] = {0, 1, 0, 1}, dj[4] = {0, 0, 1, 1};
    for (int k = 0; k < 4; ++k) {
        int ii = i + di[k], jj = j + dj[k];
        if (ii >= 0 && jj >= rows.lo && ii < grid.nx && jj < rows.hi)
            grid.at(ii, jj) += float(perArea * weights[k]);
    }
}

/// Samples [first, last) of a segment.
struct SampleRange {
    long first, last;
};

/// The samples of a segment from y0 to y1 (`samples` of them) that can splat rows of the band:
/// a slanted or vertical vector crosses many bands, and each band would otherwise walk all its
/// samples. Widened by two samples on each side against rounding; depositPoint still checks
/// every row, so the band's cells get exactly the additions, in the same order, as before.
SampleRange bandSamples(const SurfaceGrid& grid, double y0, double y1, long samples, Rows rows) {
    const double f0 = (y0 - grid.originY) / grid.pitch - 0.5 - grid.firstJ,
                 f1 = (y1 - grid.originY) / grid.pitch - 0.5 - grid.firstJ;
    const double df = f1 - f0;
    // A sample at row coordinate f splats rows floor(f) and floor(f) + 1: f in [lo - 1, hi).
    if (df == 0) return {0, samples};  // the caller keeps only a row that reaches the band
    // depositPoint's f differs from this linear one by rounding only (far below 1e-6 cells).
    constexpr double SLACK = 1e-6;
    double t0 = (double(rows.lo - 1) - SLACK - f0) / df, t1 = (double(rows.hi) + SLACK - f0) / df;
    if (t0 > t1) std::swap(t0, t1);
    // t = (s + 0.5) / samples.
    const double s0 = std::floor(t0 * double(samples) - 0.5) - 2,
                 s1 = std::ceil(t1 * double(samples) - 0.5) + 3;
    const long first = long(std::clamp(s0, 0.0, double(samples)));
    const long last = long(std::clamp(s1, 0.0, double(samples)));
    return {first, std::max(first, last)};
}

/// depositPoint's column and four weights for a block of samples of a row-parallel vector, in
/// a loop the compiler vectorises (also built for AVX2, chosen at run time; without FMA, so
/// every value is the scalar one bit for bit).
struct RowSamples {
    static constexpr int BLOCK = 256;
    double x0, dx, originX, pitch, samples, ay, perArea;
    double column[BLOCK];  ///< a whole number (kept as a double: GCC does not vectorise to int)
    float weight[4][BLOCK];

    VPSIM_AVX2_CLONES void compute(long first, int n) {
        const double base = double(first);  // exact: sample indices are far below 2^53
        // Locals: read through `this` in the loop, the members might be written by its stores,
        // and the loop would stay scalar.
        const double start = x0, step = dx, origin = originX, size = pitch, count = samples,
                     fy = ay, scale = perArea;
        double* columns = column;
        float *w0 = weight[0], *w1 = weight[1], *w2 = weight[2], *w3 = weight[3];
        for (int k = 0; k < n; ++k) {
            const double t = (base + double(k) + 0.5) / count;
            const double fx = (start + t * step - origin) / size - 0.5;
            const double cell = std::floor(fx);
            const double ax = fx - cell;
            columns[k] = cell;
            w0[k] = float(scale * ((1 - ax) * (1 - fy)));
            w1[k] = float(scale * (ax * (1 - fy)));
            w2[k] = float(scale * ((1 - ax) * fy));
            w3[k] = float(scale * (ax * fy));
        }
    }
};

/// Adds energy-per-length `q` (mJ/mm) along the segment as closely spaced samples (at most a
/// quarter cell apart), each splatted bilinearly. Bilinear splatting keeps every sample's centre
/// of energy exact, so a scan line off the cell centres is not snapped to a row: snapping would
/// alias hatch spacings against the grid into a ripple of several percent.
void depositSegment(SurfaceGrid& grid, double x0, double y0, double x1, double y1, double q,
                    Rows rows) {
    double length = std::hypot(x1 - x0, y1 - y0);
    if (length <= 0 || q <= 0) return;
    // A sample at fy splats rows floor(fy) and floor(fy) + 1: skip a segment outside the band.
    // The same for columns: a tile's deposit skips the vectors beside it.
    const double fy0 = (std::min(y0, y1) - grid.originY) / grid.pitch - 0.5 - grid.firstJ,
                 fy1 = (std::max(y0, y1) - grid.originY) / grid.pitch - 0.5 - grid.firstJ;
    if (std::floor(fy1) + 1 < rows.lo || std::floor(fy0) >= rows.hi) return;
    const double fx0 = (std::min(x0, x1) - grid.originX) / grid.pitch - 0.5 - grid.firstI,
                 fx1 = (std::max(x0, x1) - grid.originX) / grid.pitch - 0.5 - grid.firstI;
    if (std::floor(fx1) + 1 < 0 || std::floor(fx0) >= grid.nx) return;
    long samples = std::max(1L, long(std::ceil(length / (0.25 * grid.pitch))));
    double energy = q * length / double(samples);
    const SampleRange range = bandSamples(grid, y0, y1, samples, rows);
    if (y0 != y1) {
        for (long s = range.first; s < range.last; ++s) {
            double t = (s + 0.5) / double(samples);
            depositPoint(grid, x0 + t * (x1 - x0), y0 + t * (y1 - y0), energy, rows);
        }
        return;
    }
    // A row-parallel vector (most hatching): depositPoint's arithmetic with what does not change
    // along the row taken out of the loop (y0 + t * 0 is y0), the rest computed for blocks of
    // samples by RowSamples (vectorised), so the additions are the same.
    const double fy = (y0 - grid.originY) / grid.pitch - 0.5;
    const int j = int(std::floor(fy)) - grid.firstJ;
    RowSamples row;
    row.ay = fy - std::floor(fy);
    row.perArea = energy / (grid.pitch * grid.pitch);
    row.x0 = x0, row.dx = x1 - x0, row.originX = grid.originX, row.pitch = grid.pitch;
    row.samples = double(samples);
    const bool row0 = j >= rows.lo && j < rows.hi, row1 = j + 1 >= rows.lo && j + 1 < rows.hi;
    float* cells0 = row0 ? &grid.values[size_t(j) * grid.nx] : nullptr;
    float* cells1 = row1 ? &grid.values[size_t(j + 1) * grid.nx] : nullptr;
    for (long s = range.first; s < range.last; s += RowSamples::BLOCK) {
        const int n = int(std::min<long>(RowSamples::BLOCK, range.last - s));
        row.compute(s, n);
        for (int k = 0; k < n; ++k) {
            const int i = int(row.column[k]) - grid.firstI;
            const bool in0 = i >= 0 && i < grid.nx, in1 = i + 1 >= 0 && i + 1 < grid.nx;
            if (row0) {
                if (in0) cells0[i] += row.weight[0][k];
                if (in1) cells0[i + 1] += row.weight[1][k];
            }
            if (row1) {
                if (in0) cells1[i] += row.weight[2][k];
                if (in1) cells1[i + 1] += row.weight[3][k];
            }
        }
    }
}

/// Overlap lengths of the interval [a, a + size) with the window's cells [offset, offset +
/// count) along one axis (cells of the whole grid from `origin`; returned as the window's).
std::vector<std::pair<int, double>> overlaps(double a, double size, double origin, double pitch,
                                             int offset, int count) {
    std::vector<std::pair<int, double>> result;
    int first = int(std::floor((a - origin) / pitch)),
        last = int(std::floor((a + size - origin) / pitch));
    for (int c = std::max(first, offset); c <= std::min(last, offset + count - 1); ++c) {
        double lo = std::max(a, origin + c * pitch),
               hi = std::min(a + size, origin + (c + 1) * pitch);
        if (hi > lo) result.emplace_back(c - offset, hi - lo);
    }
    return result;
}

void depositMask(SurfaceGrid& grid, const plan::MaskImage& mask) {
    const double cellArea = grid.pitch * grid.pitch;
    for (int v = 0; v < mask.height; ++v) {
        auto rows = overlaps(mask.originY + v * mask.pixelPitch, mask.pixelPitch, grid.originY,
                             grid.pitch, grid.firstJ, grid.ny);
        for (int u = 0; u < mask.width; ++u) {
            float dose = mask.dose[size_t(v) * mask.width + u];
            if (dose <= 0) continue;
            auto cols = overlaps(mask.originX + u * mask.pixelPitch, mask.pixelPitch, grid.originX,
                                 grid.pitch, grid.firstI, grid.nx);
            for (const auto& [j, ly] : rows)
                for (const auto& [i, lx] : cols) grid.at(i, j) += float(dose * lx * ly / cellArea);
        }
    }
}

}  // namespace

void depositLayer(const plan::LayerPlan& layer, SurfaceGrid& grid) {
    // Bands of rows in parallel; each band takes every vector and point in plan order and splats
    // only its own rows, so every cell receives the same additions in the same order as one
    // thread would give it (the result does not depend on the threads or the band size).
    constexpr int BAND = 16;
    const int bands = (grid.ny + BAND - 1) / BAND;
    tbb::parallel_for(0, bands, [&](int b) {
        const Rows rows{b * BAND, std::min(grid.ny, (b + 1) * BAND)};
        for (const auto& v : layer.vectors)
            depositSegment(grid, v.x0, v.y0, v.x1, v.y1, v.power / v.speed, rows);
        for (const auto& p : layer.points) depositPoint(grid, p.x, p.y, p.energy, rows);
    });
    for (const auto& m : layer.masks) depositMask(grid, m);
}

}  // namespace vpsim::exposure
