#include "vpsim/optimise/laser/exposure_figures.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/text.h"
#include "vpsim/plot/plot.h"

namespace vpsim::optimise {

void writeSortedErrorFigure(const std::string& stem, const std::string& title,
                            const std::vector<std::pair<std::string, std::vector<float>>>& curves) {
    plot::LineFigure f;
    f.title = title;
    f.xLabel = "fraction of cells";
    f.yLabel = "|E - E#dtm#u| / E#dtar#u";
    for (const auto& [label, sorted] : curves) {
        plot::Curve c{label, {}, {}, plot::paletteColour(f.curves.size())};
        const size_t n = sorted.size(), step = std::max<size_t>(1, n / 400);
        for (size_t i = 0; i < n; i += step) {
            c.x.push_back(double(i) / double(std::max<size_t>(1, n - 1)));
            c.y.push_back(sorted[i]);
        }
        if (n > 0) c.x.push_back(1.0), c.y.push_back(sorted.back());
        f.curves.push_back(std::move(c));
    }
    plot::writeLineFigure(stem, f);
}

namespace {

/// `values` (nx x ny) averaged over squares of (2 r + 1) cells, clipped at the borders: a running
/// sum along x, then along y.
std::vector<float> boxAverage(const std::vector<float>& values, int nx, int ny, int r) {
    std::vector<float> rows(values.size()), out(values.size());
    for (int j = 0; j < ny; ++j) {
        const float* in = &values[size_t(j) * nx];
        double sum = 0;
        for (int i = 0; i < std::min(r, nx); ++i) sum += in[i];
        for (int i = 0; i < nx; ++i) {
            if (i + r < nx) sum += in[i + r];
            if (i - r - 1 >= 0) sum -= in[i - r - 1];
            rows[size_t(j) * nx + i] =
                float(sum / (std::min(nx - 1, i + r) - std::max(0, i - r) + 1));
        }
    }
    for (int i = 0; i < nx; ++i) {
        double sum = 0;
        for (int j = 0; j < std::min(r, ny); ++j) sum += rows[size_t(j) * nx + i];
        for (int j = 0; j < ny; ++j) {
            if (j + r < ny) sum += rows[size_t(j + r) * nx + i];
            if (j - r - 1 >= 0) sum -= rows[size_t(j - r - 1) * nx + i];
            out[size_t(j) * nx + i] =
                float(sum / (std::min(ny - 1, j + r) - std::max(0, j - r) + 1));
        }
    }
    return out;
}

}  // namespace

void writeExposureMapFigure(const std::string& stem, const std::string& title,
                            const exposure::SurfaceGrid& map, const geometry::PolygonSet* region,
                            double targetDose, double criticalDose, double smoothing) {
    constexpr double PER_CM2 = 100.0;  // mJ/mm^2 -> mJ/cm^2
    plot::MapFigure f;
    f.title = title;
    f.nx = map.nx, f.ny = map.ny;
    f.x0 = map.originX, f.x1 = map.originX + map.nx * map.pitch;
    f.y0 = map.originY, f.y1 = map.originY + map.ny * map.pitch;
    f.values.resize(map.values.size());
    size_t above = 0;
    const double hi = 1.5 * targetDose * PER_CM2;
    for (size_t c = 0; c < map.values.size(); ++c) {
        f.values[c] = float(map.values[c] * PER_CM2);
        above += f.values[c] > hi;
    }
    f.scale = {plot::ColourMap::Sequential,     0.0,   hi,
               "surface exposure (mJ/cm#u2#d)", false, above > 0};
    // Smoothed, the line marks where the averaged exposure falls 10% below Etar (inside, the
    // average is Etar to within the ripple left, which would otherwise wander about the level).
    const int reach = int(std::floor(0.5 * smoothing / map.pitch));
    if (reach > 0)
        f.outlines.push_back({"0.9 E#dtar#u = " + formatNumber(0.9 * targetDose * PER_CM2, 3) +
                                  " mJ/cm#u2#d, averaged over " +
                                  formatQuantity(smoothing * 1e3, "um") + " squares",
                              boxAverage(f.values, f.nx, f.ny, reach),
                              0.9 * targetDose * PER_CM2,
                              {255, 80, 200},
                              true});
    else
        f.outlines.push_back({"E#dtar#u = " + formatNumber(targetDose * PER_CM2, 3) + " mJ/cm#u2#d",
                              {},
                              targetDose * PER_CM2,
                              {255, 80, 200},
                              true});
    if (criticalDose > 0)
        f.outlines.push_back({"E#dc#u = " + formatNumber(criticalDose * PER_CM2, 3) + " mJ/cm#u2#d",
                              {},
                              criticalDose * PER_CM2,
                              {255, 127, 14},
                              false});
    if (region) {
        plot::Curve outline{"model outline", {}, {}, {230, 30, 30}};
        for (const auto& contour : region->contours()) {
            for (const auto& v : contour) outline.x.push_back(v.x), outline.y.push_back(v.y);
            if (!contour.empty())  // closed, then a break before the next contour
                outline.x.insert(outline.x.end(), {contour.front().x, NAN}),
                    outline.y.insert(outline.y.end(), {contour.front().y, NAN});
        }
        f.lines.push_back(std::move(outline));
    }
    f.note = formatNumber(100.0 * double(above) / double(std::max<size_t>(1, f.values.size())), 3) +
             "% of the cells above 1.5 E#dtar#u (drawn at the top of the scale)";
    plot::writeMapFigure(stem, f);
}

}  // namespace vpsim::optimise
