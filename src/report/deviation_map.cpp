#include "vpsim/report/deviation_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vpsim/core/text.h"
#include "vpsim/plot/plot.h"

namespace vpsim::report {
namespace {

/// A top-view raster of meshes: each pixel keeps the highest surface above it.
struct TopView {
    int nx = 0, ny = 0;
    double x0 = 0, y0 = 0, pitch = 1;
    std::vector<double> height;  ///< highest z seen, -inf where nothing
    std::vector<float> value;    ///< interpolated per-vertex value at that surface

    /// Rasterises every triangle; `values` (per vertex, may be empty) are interpolated.
    void draw(const geometry::Mesh& mesh, const std::vector<float>& values) {
        for (const auto& t : mesh.triangles) {
            const glm::dvec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]],
                             &c = mesh.vertices[t[2]];
            const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
            if (std::abs(det) < 1e-18) continue;  // seen edge-on from above
            auto cell = [&](double v, double o) { return (v - o) / pitch - 0.5; };
            const int i0 = std::max(0, int(std::ceil(cell(std::min({a.x, b.x, c.x}), x0))));
            const int i1 = std::min(nx - 1, int(std::floor(cell(std::max({a.x, b.x, c.x}), x0))));
            const int j0 = std::max(0, int(std::ceil(cell(std::min({a.y, b.y, c.y}), y0))));
            const int j1 = std::min(ny - 1, int(std::floor(cell(std::max({a.y, b.y, c.y}), y0))));
            for (int j = j0; j <= j1; ++j)
                for (int i = i0; i <= i1; ++i) {
                    const double px = x0 + (i + 0.5) * pitch, py = y0 + (j + 0.5) * pitch;
                    const double u = ((px - a.x) * (c.y - a.y) - (c.x - a.x) * (py - a.y)) / det;
                    const double v = ((b.x - a.x) * (py - a.y) - (px - a.x) * (b.y - a.y)) / det;
                    if (u < -1e-9 || v < -1e-9 || u + v > 1 + 1e-9) continue;
                    const double z = a.z + u * (b.z - a.z) + v * (c.z - a.z);
                    const size_t k = size_t(j) * nx + i;
                    if (z <= height[k]) continue;
                    height[k] = z;
                    if (!values.empty())
                        value[k] = float(values[t[0]] + u * (values[t[1]] - values[t[0]]) +
                                         v * (values[t[2]] - values[t[0]]));
                }
        }
    }
    std::vector<float> covered() const {
        std::vector<float> mask(height.size());
        for (size_t k = 0; k < height.size(); ++k) mask[k] = std::isfinite(height[k]) ? 1.f : 0.f;
        return mask;
    }
};

TopView topView(const geometry::Bounds& b) {
    TopView view;
    const double sx = b.hi.x - b.lo.x, sy = b.hi.y - b.lo.y, pad = 0.04 * std::max(sx, sy);
    view.pitch = std::max(sx, sy) * 1.08 / 400;
    view.x0 = b.lo.x - pad, view.y0 = b.lo.y - pad;
    view.nx = int(std::ceil((sx + 2 * pad) / view.pitch));
    view.ny = int(std::ceil((sy + 2 * pad) / view.pitch));
    view.height.assign(size_t(view.nx) * view.ny, -std::numeric_limits<double>::infinity());
    view.value.assign(view.height.size(), std::numeric_limits<float>::quiet_NaN());
    return view;
}

std::string micrometres(double mm) {
    return formatNumber(mm * 1000, 3);
}

/// The round step above the 95th percentile `p95`: 1, 2, 2.5 or 5 times a power of ten.
double roundLimit(double p95) {
    p95 = std::max(1e-6, p95);
    const double power = std::pow(10.0, std::floor(std::log10(p95)));
    for (double m : {1.0, 2.0, 2.5, 5.0})
        if (m * power >= p95) return m * power;
    return 10 * power;
}

}  // namespace

DeviationScale deviationScale(const validate::DeviationStatistics& statistics) {
    DeviationScale s;
    if (statistics.count() == 0) return s;
    s.limit = roundLimit(statistics.magnitudeAtRank(statistics.count() * 95 / 100));
    s.beyond = double(statistics.countAbove(s.limit)) / double(statistics.count());
    return s;
}

DeviationScale writeDeviationFigures(const std::string& directory,
                                     const validate::StreamingCuredSurface::View& cured,
                                     const validate::DeviationStatistics& statistics,
                                     const geometry::Mesh& part) {
    const std::vector<float>& deviations = cured.deviations;
    if (statistics.count() == 0 || deviations.empty() ||
        deviations.size() != cured.mesh.vertices.size())
        return {};
    const DeviationScale scale = deviationScale(statistics);
    const double lo = statistics.minimum(), hi = statistics.maximum();
    const double limit = std::max(1e-6, std::max(std::abs(lo), std::abs(hi)));
    const int bins = 60;
    plot::Curve histogram{"", {}, {}, {31, 119, 180}, false};
    const std::vector<uint64_t> counts = statistics.histogram(-limit, limit, bins);
    for (int b = 0; b < bins; ++b) {  // a step outline of the histogram, in µm
        const double x0 = -limit + 2 * limit * b / bins, x1 = -limit + 2 * limit * (b + 1) / bins;
        histogram.x.insert(histogram.x.end(), {x0 * 1000, x1 * 1000});
        histogram.y.insert(histogram.y.end(), {double(counts[b]), double(counts[b])});
    }
    plot::LineFigure h;
    h.title = "Signed deviation of the cured surface from the model";
    h.xLabel = "deviation (µm), positive: outside the model";
    h.yLabel = "cured-surface vertices";
    h.curves = {histogram};
    plot::writeLineFigure(directory + "/deviation_histogram", h);

    geometry::Bounds b = cured.mesh.bounds();
    const geometry::Bounds pb = part.bounds();
    b.add(pb.lo), b.add(pb.hi);
    TopView curedView = topView(b), modelView = curedView;
    std::vector<float> microns(deviations.size());
    for (size_t i = 0; i < deviations.size(); ++i) microns[i] = deviations[i] * 1000.0f;
    curedView.draw(cured.mesh, microns);
    modelView.draw(part, {});
    plot::MapFigure f;
    f.title = "Cured surface from above: deviation of its top surface";
    f.nx = curedView.nx, f.ny = curedView.ny;
    f.x0 = curedView.x0, f.x1 = f.x0 + f.nx * curedView.pitch;
    f.y0 = curedView.y0, f.y1 = f.y0 + f.ny * curedView.pitch;
    f.values = curedView.value;
    const double l = scale.limit * 1000;
    f.scale = {plot::ColourMap::Diverging,
               -l,
               l,
               "deviation (µm), + outside the model",
               lo * 1000 < -l,
               hi * 1000 > l};
    f.outlines.push_back({"model silhouette", modelView.covered(), 0.5, {0, 0, 0}, true});
    f.outlines.push_back({"cured silhouette", curedView.covered(), 0.5, {120, 40, 160}, false});
    f.note = formatNumber(100 * scale.beyond, 2) + "% of the cured surface (vertices) beyond ±" +
             micrometres(scale.limit) + " µm; grey: nothing cured";
    plot::writeMapFigure(directory + "/deviation_map_top", f);
    return scale;
}

}  // namespace vpsim::report
