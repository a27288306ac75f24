// Map figures: a scalar field on a grid with axes, colour bar, scale bar, outlines and lines.

#include <algorithm>
#include <cmath>
#include <limits>

#include "plplot_page.h"
#include "vpsim/core/error.h"
#include "vpsim/core/image.h"
#include "vpsim/core/text.h"
#include "vpsim/plot/plot.h"

namespace vpsim::plot {
namespace {

/// The colour of t in [0, 1] on `map` (PLplot's cmap1 as setColourMap sets it).
Rgb mapColour(ColourMap map, double t) {
    t = std::clamp(t, 0.0, 1.0);
    if (map == ColourMap::Diverging) {
        const double a = std::abs(2 * t - 1), w = 0.97;
        const double end[3] = {t < 0.5 ? 0.13 : 0.70, t < 0.5 ? 0.40 : 0.09, t < 0.5 ? 0.67 : 0.17};
        auto c = [&](int k) { return uint8_t(std::lround(255 * (w + (end[k] - w) * a))); };
        return {c(0), c(1), c(2)};
    }
    if (map == ColourMap::Grey) {
        const uint8_t g = uint8_t(std::lround(255 * t));
        return {g, g, g};
    }
    Rgb c;
    viridis(t, c.r, c.g, c.b);
    return c;
}

/// The map's cells as pixels (rows from the top), no data in grey.
RgbImage cellColours(const MapFigure& f) {
    RgbImage image(f.nx, f.ny, 150);
    for (int j = 0; j < f.ny; ++j)
        for (int i = 0; i < f.nx; ++i) {
            const float v = f.values[size_t(j) * f.nx + i];
            if (!std::isfinite(v)) continue;
            const Rgb c = mapColour(f.scale.map, (v - f.scale.lo) / (f.scale.hi - f.scale.lo));
            image.set(i, f.ny - 1 - j, c.r, c.g, c.b);
        }
    return image;
}

/// PLplot's cmap1 as mapColour gives it.
void setColourMap(ColourMap map) {
    PLINT r[256], g[256], b[256];
    for (int k = 0; k < 256; ++k) {
        const Rgb c = mapColour(map, k / 255.0);
        r[k] = c.r, g[k] = c.g, b[k] = c.b;
    }
    plscmap1n(256);
    plscmap1(r, g, b, 256);
}

/// The outlines' contour lines in the map's units, each outline's polylines broken by NaN (traced
/// once for both devices).
std::vector<Curve> outlineCurves(const MapFigure& f) {
    std::vector<Curve> curves;
    const double dx = (f.x1 - f.x0) / f.nx, dy = (f.y1 - f.y0) / f.ny;
    for (const Outline& o : f.outlines) {
        const std::vector<float>& field = o.field.empty() ? f.values : o.field;
        if (field.size() != f.values.size()) continue;
        Curve c{o.label, {}, {}, o.colour, o.dashed};
        for (const ContourLine& line : contourLines(field, f.nx, f.ny, o.level)) {
            for (size_t k = 0; k < line.x.size(); ++k)
                c.x.push_back(f.x0 + (line.x[k] + 0.5) * dx),
                    c.y.push_back(f.y0 + (line.y[k] + 0.5) * dy);
            c.x.push_back(NAN), c.y.push_back(NAN);
        }
        curves.push_back(std::move(c));
    }
    return curves;
}

std::string formatLength(double length, const std::string& unit) {
    if (unit == "mm" && length < 1)
        return formatNumber(std::round(length * 1000 * 1e6) / 1e6, 6) + " µm";
    return formatNumber(length, 6) + " " + unit;
}

/// A round length about a fifth of the width, lower left, on a white box; `pixel` is the height
/// of one pixel in the map's units.
void scaleBar(const MapFigure& f, double pixel) {
    const double span = f.x1 - f.x0, length = niceStep(span, 5);
    const double x = f.x0 + 0.03 * span, y = f.y0 + 10 * pixel;
    PLFLT bx[] = {x - 6 * pixel, x + length + 6 * pixel, x + length + 6 * pixel, x - 6 * pixel};
    PLFLT by[] = {y - 6 * pixel, y - 6 * pixel, y + 24 * pixel, y + 24 * pixel};
    plcol0(WHITE);
    plfill(4, bx, by);
    plcol0(BLACK);
    plwidth(3);
    pljoin(x, y, x + length, y);
    plwidth(1);
    const std::string label = formatLength(length, f.scaleUnit);
    plptex(x + length / 2, y + 11 * pixel, 1, 0, 0.5, label.c_str());
}

/// Mean of the finite values of `field` over the cells [i0, i1) x [j0, j1); NaN when none.
float blockMean(const std::vector<float>& field, int nx, int i0, int i1, int j0, int j1) {
    double sum = 0;
    int count = 0;
    for (int j = j0; j < j1; ++j)
        for (int i = i0; i < i1; ++i) {
            const float v = field[size_t(j) * nx + i];
            if (std::isfinite(v)) sum += v, ++count;
        }
    return count > 0 ? float(sum / count) : std::numeric_limits<float>::quiet_NaN();
}

}  // namespace

MapFigure downsampled(const MapFigure& f, int maxCells) {
    const int factor = (std::max(f.nx, f.ny) + maxCells - 1) / std::max(1, maxCells);
    if (factor <= 1) return f;
    MapFigure out = f;
    out.nx = (f.nx + factor - 1) / factor, out.ny = (f.ny + factor - 1) / factor;
    // Cell i of the result covers the cells [i * nx / nx', (i + 1) * nx / nx') of the figure, so
    // the outer edges stay where they were.
    auto shrink = [&](const std::vector<float>& field) {
        std::vector<float> result(size_t(out.nx) * out.ny);
        for (int j = 0; j < out.ny; ++j)
            for (int i = 0; i < out.nx; ++i)
                result[size_t(j) * out.nx + i] =
                    blockMean(field, f.nx, int(int64_t(i) * f.nx / out.nx),
                              int(int64_t(i + 1) * f.nx / out.nx), int(int64_t(j) * f.ny / out.ny),
                              int(int64_t(j + 1) * f.ny / out.ny));
        return result;
    };
    out.values = shrink(f.values);
    for (Outline& o : out.outlines)
        if (o.field.size() == f.values.size()) o.field = shrink(o.field);
    return out;
}

void writeMapFigure(const std::string& stem, const MapFigure& figure) {
    if (figure.nx < 1 || figure.ny < 1 || figure.values.size() != size_t(figure.nx) * figure.ny ||
        !(figure.x1 > figure.x0) || !(figure.y1 > figure.y0))
        throw InputError("map figure " + stem + ": the grid does not match its values");
    const MapFigure f = downsampled(figure);
    // Plot area in pixels at the true aspect ratio, about 640 px wide or 560 px tall.
    const double aspect = (f.y1 - f.y0) / (f.x1 - f.x0);
    double pw = 640, ph = pw * aspect;
    if (ph > 560) ph = 560, pw = ph / aspect;
    size_t legendEntries = f.outlines.size(), longest = 0;
    for (const Outline& o : f.outlines) longest = std::max(longest, drawnLength(o.label));
    for (const Curve& c : f.lines)
        legendEntries += !c.label.empty(), longest = std::max(longest, drawnLength(c.label));
    const int columns = legendColumns(legendEntries, longest, pw);
    const int legendRows = int((legendEntries + columns - 1) / columns);
    const double left = 90, right = 210, top = 50;
    const double bottom = (f.note.empty() ? 115 : 140) + 25.0 * std::max(0, legendRows - 1);
    const int width = int(left + std::max(pw, 200.0) + right),
              height = int(top + std::max(ph, 60.0) + bottom);
    const ColourScale& s = f.scale;
    // The cells under the plot area, which PLplot's viewport puts `bottom` above the page's foot.
    const Underlay cells{cellColours(f), left, height - bottom - ph, pw, ph};
    const std::vector<Curve> outlines = outlineCurves(f);
    plotTwice(
        stem, width, height,
        [&](bool) {
            plvpor(left / width, (left + pw) / width, bottom / height, (bottom + ph) / height);
            plwind(f.x0, f.x1, f.y0, f.y1);
            setColourMap(s.map);  // the colour bar's
            std::vector<LegendEntry> entries;
            PLINT index = FIRST_FREE;
            for (const Curve& c : outlines) {
                useColour(index, c.colour);
                pllsty(c.dashed ? 2 : 1);
                plwidth(2);
                polyline(c.x, c.y);
                entries.push_back({c.label, index, c.dashed ? 2 : 1, false});
                ++index;
            }
            for (const Curve& c : f.lines) {
                useColour(index, c.colour);
                drawCurve(c);
                if (!c.label.empty()) entries.push_back({c.label, index, c.dashed ? 2 : 1, false});
                ++index;
            }
            pllsty(1);
            plwidth(1);
            if (f.scaleBar && ph >= 120) scaleBar(f, (f.y1 - f.y0) / ph);  // leave short maps clear
            plcol0(BLACK);
            plbox("bcnst", 0, 0, "bcnstv", 0, 0);
            plmtex("t", 1.5, 0.5, 0.5, f.title.c_str());
            plmtex("b", 3.2, 0.5, 0.5, f.xLabel.c_str());
            plmtex("l", 5.0, 0.5, 0.5, f.yLabel.c_str());
            // Colour bar right of the plot, as tall as the plot (at least 150 px).
            const char* axis = "bcvtm";
            const char* label = s.label.c_str();
            PLINT labelOpt = PL_COLORBAR_LABEL_RIGHT, nValues = 2, ticks = 0;
            PLFLT ticksSpacing = 0, range[] = {s.lo, s.hi};
            const PLFLT* values[] = {range};
            PLFLT cw = 0, ch = 0;
            plcolorbar(&cw, &ch,
                       PL_COLORBAR_IMAGE | (s.capLow ? PL_COLORBAR_CAP_LOW : 0) |
                           (s.capHigh ? PL_COLORBAR_CAP_HIGH : 0),
                       PL_POSITION_RIGHT | PL_POSITION_OUTSIDE | PL_POSITION_VIEWPORT, 0.03, 0.0,
                       0.04 * 640 / pw, std::max(1.0, 150 / ph) * 0.95, WHITE, BLACK, 1, 0.0, 1.0,
                       0, 0, 1, &labelOpt, &label, 1, &axis, &ticksSpacing, &ticks, &nValues,
                       values);
            if (!entries.empty())
                legend(entries, PL_POSITION_BOTTOM | PL_POSITION_OUTSIDE | PL_POSITION_VIEWPORT,
                       0.0, 55.0 / ph, columns);
            if (!f.note.empty())
                plmtex("b", 7.2 + (entries.empty() ? 0 : 0.5) + 1.6 * std::max(0, legendRows - 1),
                       0.0, 0.0, f.note.c_str());
        },
        &cells);
}

}  // namespace vpsim::plot
