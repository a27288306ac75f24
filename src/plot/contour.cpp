// Contour lines of a field on a grid by marching squares, joined into polylines (PLplot's plcont
// writes every cell's piece as its own line: thousands of SVG elements, dashes restarting in
// each cell, and the tracing done again for each device).

#include <array>
#include <cmath>
#include <utility>

#include "vpsim/plot/plot.h"

namespace vpsim::plot {
namespace {

/// Edges between neighbouring cell centres: 2 (j nx + i) runs from (i, j) to (i + 1, j),
/// 2 (j nx + i) + 1 from (i, j) to (i, j + 1).
struct Grid {
    const std::vector<float>& field;
    int nx, ny;
    double level;

    bool above(int i, int j) const {
        const float v = field[size_t(j) * nx + i];
        return std::isfinite(v) && v > level;  // no data is below, as PLplot's lowest value
    }
    int64_t horizontal(int i, int j) const { return 2 * (int64_t(j) * nx + i); }
    int64_t vertical(int i, int j) const { return 2 * (int64_t(j) * nx + i) + 1; }

    /// Where the level crosses `edge`, linearly between its ends; at the finite end when the
    /// other has no data.
    std::array<double, 2> crossing(int64_t edge) const {
        const int64_t cell = edge / 2;
        const int i = int(cell % nx), j = int(cell / nx), di = edge % 2 ? 0 : 1, dj = 1 - di;
        const double a = field[size_t(cell)], b = field[size_t(j + dj) * nx + i + di];
        double t = !std::isfinite(a) ? 1.0 : !std::isfinite(b) ? 0.0 : (level - a) / (b - a);
        t = std::isfinite(t) ? std::fmin(1.0, std::fmax(0.0, t)) : 0.5;
        return {i + t * di, j + t * dj};
    }
};

}  // namespace

std::vector<ContourLine> contourLines(const std::vector<float>& field, int nx, int ny,
                                      double level) {
    std::vector<ContourLine> lines;
    if (nx < 2 || ny < 2 || field.size() != size_t(nx) * ny) return lines;
    const Grid g{field, nx, ny, level};
    // Each square's pieces as pairs of edges; side k of square (i, j): 0 bottom, 1 right, 2 top,
    // 3 left. Corners: bit 0 (i, j), 1 (i + 1, j), 2 (i + 1, j + 1), 3 (i, j + 1).
    static const int pieces[16][4] = {
        {-1, -1, -1, -1}, {0, 3, -1, -1}, {0, 1, -1, -1}, {3, 1, -1, -1},
        {1, 2, -1, -1},   {0, 1, 2, 3},   {0, 2, -1, -1}, {3, 2, -1, -1},
        {2, 3, -1, -1},   {0, 2, -1, -1}, {0, 3, 1, 2},   {1, 2, -1, -1},
        {3, 1, -1, -1},   {0, 1, -1, -1}, {0, 3, -1, -1}, {-1, -1, -1, -1}};
    std::vector<std::array<int64_t, 2>> segments;
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            const int corners = g.above(i, j) | g.above(i + 1, j) << 1 |
                                g.above(i + 1, j + 1) << 2 | g.above(i, j + 1) << 3;
            if (corners == 0 || corners == 15) continue;
            const int64_t side[4] = {g.horizontal(i, j), g.vertical(i + 1, j),
                                     g.horizontal(i, j + 1), g.vertical(i, j)};
            const int* which = pieces[corners];
            if (corners == 5 || corners == 10) {  // a saddle: the mean of the corners decides
                double mean = 0;
                for (const auto& [di, dj] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
                    const float v = field[size_t(j + dj) * nx + i + di];
                    mean += std::isfinite(v) ? v : -1e300;
                }
                // The table joins the above corners through the centre; below it, they part.
                static const int apart[2][4] = {{0, 3, 1, 2}, {0, 1, 2, 3}};
                if (!(mean / 4 > level)) which = apart[corners == 10];
            }
            for (int k = 0; k < 4 && which[k] >= 0; k += 2)
                segments.push_back({side[which[k]], side[which[k + 1]]});
        }
    // Join pieces that share an edge (at most two do): open lines from their loose ends first,
    // then the closed ones.
    std::vector<std::array<int, 2>> onEdge(size_t(2) * nx * ny, {-1, -1});
    for (int s = 0; s < int(segments.size()); ++s)
        for (const int64_t e : segments[size_t(s)])
            onEdge[size_t(e)][onEdge[size_t(e)][0] >= 0] = s;
    std::vector<char> used(segments.size(), 0);
    auto follow = [&](int s, int64_t from) {
        ContourLine line;
        auto add = [&](int64_t edge) {
            const std::array<double, 2> p = g.crossing(edge);
            line.x.push_back(p[0]), line.y.push_back(p[1]);
        };
        add(from);
        while (s >= 0 && !used[size_t(s)]) {
            used[size_t(s)] = 1;
            const int64_t to =
                segments[size_t(s)][0] == from ? segments[size_t(s)][1] : segments[size_t(s)][0];
            add(to);
            const std::array<int, 2>& next = onEdge[size_t(to)];
            s = next[0] == s ? next[1] : next[0];
            from = to;
        }
        lines.push_back(std::move(line));
    };
    for (int s = 0; s < int(segments.size()); ++s)
        for (const int64_t e : segments[size_t(s)])
            if (!used[size_t(s)] && onEdge[size_t(e)][1] < 0) follow(s, e);
    for (int s = 0; s < int(segments.size()); ++s)
        if (!used[size_t(s)]) follow(s, segments[size_t(s)][0]);
    return lines;
}

}  // namespace vpsim::plot
