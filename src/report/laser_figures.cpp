#include "vpsim/report/laser_figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "vpsim/core/image.h"
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/report/summary_tables.h"

namespace vpsim::report {
namespace {

/// Round tick step near span/5 (1, 2 or 5 times a power of ten).
double tickStep(double span) {
    double raw = span / 5, power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0})
        if (m * power >= raw) return m * power;
    return 10 * power;
}

/// The map as a viridis PNG (rows from the top), 0 .. hi, read back as bytes.
std::string heatMapPng(const std::string& path, const exposure::SurfaceGrid& map, double hi) {
    std::vector<float> flipped(map.values.size());
    for (int j = 0; j < map.ny; ++j)
        for (int i = 0; i < map.nx; ++i)
            flipped[size_t(map.ny - 1 - j) * map.nx + i] = map.values[size_t(j) * map.nx + i];
    const std::string png = path + ".png";
    writePng(png, heatMap(flipped, map.nx, map.ny, 0.0, hi));
    std::string bytes = readFile(png);
    std::remove(png.c_str());
    return bytes;
}

/// Colour bar in mJ/cm^2 (x100 the internal mJ/mm^2) at x `bx`, with Etar and Ec marked.
void colourBar(std::ostringstream& svg, double bx, double top, double h, double hi,
               double targetDose, double criticalDose) {
    const double bw = 16;
    for (int k = 0; k < 64; ++k) {
        uint8_t r, g, b;
        viridis((k + 0.5) / 64, r, g, b);
        svg << "<rect x='" << bx << "' y='" << top + h * (1 - (k + 1) / 64.0) << "' width='" << bw
            << "' height='" << h / 64 + 0.5 << "' fill='rgb(" << int(r) << ',' << int(g) << ','
            << int(b) << ")'/>\n";
    }
    auto mark = [&](double dose, const std::string& label) {
        double y = top + h * (1 - dose / hi);
        svg << "<line x1='" << bx << "' x2='" << bx + bw + 4 << "' y1='" << y << "' y2='" << y
            << "' stroke='black'/><text x='" << bx + bw + 6 << "' y='" << y + 4 << "'>"
            << htmlEscape(label) << "</text>\n";
    };
    mark(0, "0");
    mark(hi, formatNumber(hi * 100, 3));
    mark(targetDose, "Etar " + formatNumber(targetDose * 100, 3));
    if (criticalDose > 0 && criticalDose < hi)
        mark(criticalDose, "Ec " + formatNumber(criticalDose * 100, 3));
    svg << "<text x='" << bx << "' y='" << top - 8 << "'>mJ/cm&#178;</text>\n";
}

}  // namespace

void writeSortedErrorFigure(const std::string& path,
                            const std::vector<std::pair<std::string, std::vector<float>>>& curves) {
    std::vector<PlotSeries> series;
    for (const auto& [label, sorted] : curves) {
        PlotSeries s;
        s.label = label;
        const size_t n = sorted.size(), step = std::max<size_t>(1, n / 400);
        for (size_t i = 0; i < n; i += step) {
            s.x.push_back(double(i) / double(std::max<size_t>(1, n - 1)));
            s.y.push_back(sorted[i]);
        }
        if (n > 0) s.x.push_back(1.0), s.y.push_back(sorted.back());
        series.push_back(std::move(s));
    }
    writeSvgLinePlot(path, "Sorted exposure error over the part plus Reff (seed 000 Fig. 23)",
                     "fraction of cells", "|E - Etm| / Etar", series);
}

void writeLayerExposureFigure(const std::string& path, const exposure::SurfaceGrid& map,
                              const geometry::PolygonSet& region, double targetDose,
                              double criticalDose, const std::string& title) {
    const double hi = 1.5 * targetDose;
    const double x0 = map.originX, y0 = map.originY;
    const double x1 = x0 + map.nx * map.pitch, y1 = y0 + map.ny * map.pitch;
    const double scale = 420.0 / std::max(x1 - x0, y1 - y0);  // pixels per mm
    const double w = (x1 - x0) * scale, h = (y1 - y0) * scale, left = 60, top = 40;
    auto px = [&](double x) { return left + (x - x0) * scale; };
    auto py = [&](double y) { return top + (y1 - y) * scale; };
    std::ostringstream svg;
    svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << left + w + 130 << "' height='"
        << top + h + 60 << "' font-family='sans-serif' font-size='12'>\n<text x='" << left
        << "' y='20' font-size='14'>" << htmlEscape(title) << "</text>\n<image x='" << left
        << "' y='" << top << "' width='" << w << "' height='" << h
        << "' preserveAspectRatio='none' style='image-rendering:pixelated' href='data:image/png;"
           "base64,"
        << base64(heatMapPng(path, map, hi)) << "'/>\n";
    for (const auto& contour : region.contours()) {
        svg << "<polygon fill='none' stroke='red' stroke-width='1' points='";
        for (const auto& v : contour) svg << px(v.x) << ',' << py(v.y) << ' ';
        svg << "'/>\n";
    }
    svg << "<rect x='" << left << "' y='" << top << "' width='" << w << "' height='" << h
        << "' fill='none' stroke='black'/>\n";
    const double xs = tickStep(x1 - x0), ys = tickStep(y1 - y0);
    for (double x = std::ceil(x0 / xs) * xs; x <= x1 + 1e-12; x += xs)
        svg << "<line x1='" << px(x) << "' x2='" << px(x) << "' y1='" << top + h << "' y2='"
            << top + h + 5 << "' stroke='black'/><text x='" << px(x) << "' y='" << top + h + 18
            << "' text-anchor='middle'>" << formatNumber(x, 3) << "</text>\n";
    for (double y = std::ceil(y0 / ys) * ys; y <= y1 + 1e-12; y += ys)
        svg << "<line x1='" << left - 5 << "' x2='" << left << "' y1='" << py(y) << "' y2='"
            << py(y) << "' stroke='black'/><text x='" << left - 8 << "' y='" << py(y) + 4
            << "' text-anchor='end'>" << formatNumber(y, 3) << "</text>\n";
    svg << "<text x='" << left + w / 2 << "' y='" << top + h + 40
        << "' text-anchor='middle'>x (mm)</text><text x='15' y='" << top + h / 2
        << "' transform='rotate(-90 15 " << top + h / 2
        << ")' text-anchor='middle'>y (mm)</text>\n";
    colourBar(svg, left + w + 20, top, h, hi, targetDose, criticalDose);
    svg << "</svg>\n";
    writeFileAtomic(path, svg.str());
}

}  // namespace vpsim::report
