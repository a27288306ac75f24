#include "vpsim/report/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <mutex>

#include <plplot.h>

#include "vpsim/core/error.h"
#include "vpsim/core/image.h"
#include "vpsim/core/io.h"
#include "vpsim/report/summary_tables.h"

namespace vpsim::report {
namespace {

/// PLplot keeps its streams in global state: one figure at a time.
std::mutex& plplotMutex() {
    static std::mutex mutex;
    return mutex;
}

constexpr PLINT BLACK = 1, GREY = 2, LIGHT = 3, WHITE = 4, FIRST_FREE = 5;

/// Draws one figure on both devices: `draw(svg)` runs inside an initialised page; `svgImage`, when
/// given, is placed under everything PLplot draws in the SVG (a raster as a PNG <image>, since
/// PLplot's SVG driver would write one rectangle per cell).
void plotTwice(const std::string& stem, int width, int height,
               const std::function<void(bool svg)>& draw, const std::string& svgImage = "") {
    std::lock_guard<std::mutex> lock(plplotMutex());
    for (const char* device : {"svg", "pngcairo"}) {
        const std::string path = stem + (device[0] == 's' ? ".svg" : ".png");
        writePathAtomic(path, [&](const std::string& temporary) {
            PLINT stream = 0;
            plmkstrm(&stream);
            plsdev(device);
            plsfnam(temporary.c_str());
            const std::string geometry = std::to_string(width) + "x" + std::to_string(height);
            plsetopt("geometry", geometry.c_str());
            plscmap0n(32);
            plscolbg(255, 255, 255);
            plscol0(BLACK, 0, 0, 0);
            plscol0(GREY, 150, 150, 150);
            plscol0(LIGHT, 225, 225, 225);
            plscol0(WHITE, 255, 255, 255);
            plinit();
            pladv(0);
            plschr(0, 0.85);
            draw(device[0] == 's');
            plend1();
            if (device[0] == 's' && !svgImage.empty()) {
                std::string svg = readFile(temporary);
                const size_t background = svg.find("<rect");
                const size_t end = svg.find("/>", background);
                if (background == std::string::npos || end == std::string::npos)
                    throw InputError(path + ": PLplot's SVG has no background to draw over");
                svg.insert(end + 2, "\n" + svgImage);
                std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
                out << svg;
                if (!out.flush()) throw InputError(path + ": cannot be written");
            }
        });
    }
}

void colour(PLINT index, Rgb c) {
    plscol0(index, c.r, c.g, c.b);
    plcol0(index);
}

/// Lines between consecutive finite points.
void polyline(const std::vector<double>& x, const std::vector<double>& y) {
    std::vector<PLFLT> px, py;
    auto flush = [&] {
        if (px.size() > 1) plline(PLINT(px.size()), px.data(), py.data());
        px.clear(), py.clear();
    };
    for (size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
        if (std::isfinite(x[i]) && std::isfinite(y[i]))
            px.push_back(x[i]), py.push_back(y[i]);
        else
            flush();
    }
    flush();
}

/// A legend of lines (no symbols) at `position`, offset (x, y) in viewport fractions.
void lineLegend(const std::vector<std::string>& labels, const std::vector<PLINT>& colours,
                const std::vector<PLINT>& styles, PLINT position, double x, double y, int columns) {
    const PLINT n = PLINT(labels.size());
    if (n == 0) return;
    std::vector<PLINT> opts(n, PL_LEGEND_LINE), textColours(n, BLACK), zeros(n, 0);
    std::vector<PLFLT> widths(n, 2.0), ones(n, 1.0);
    std::vector<const char*> text, symbols(n, "");
    for (const std::string& label : labels) text.push_back(label.c_str());
    PLFLT w = 0, h = 0;
    pllegend(&w, &h, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX, position, x, y, 0.07, GREY,
             BLACK, 1, (n + columns - 1) / columns, columns, n, opts.data(), 0.8, 0.8, 2.0, 0.0,
             textColours.data(), text.data(), zeros.data(), zeros.data(), ones.data(),
             widths.data(), colours.data(), styles.data(), widths.data(), zeros.data(), ones.data(),
             zeros.data(), symbols.data());
}

/// The colour of t in [0, 1] on `map` (PLplot's cmap1 as setColourMap sets it).
Rgb mapColour(ColourMap map, double t) {
    t = std::clamp(t, 0.0, 1.0);
    if (map == ColourMap::Diverging) {
        const double a = std::abs(2 * t - 1), w = 0.97;
        const double end[3] = {t < 0.5 ? 0.13 : 0.70, t < 0.5 ? 0.40 : 0.09, t < 0.5 ? 0.67 : 0.17};
        auto c = [&](int k) { return uint8_t(std::lround(255 * (w + (end[k] - w) * a))); };
        return {c(0), c(1), c(2)};
    }
    Rgb c;
    viridis(t, c.r, c.g, c.b);
    return c;
}

/// The map's cells as a PNG (rows from the top), no data in grey, as an SVG <image> over the
/// plot area at (left, top) of size (w, h) in the page's units.
std::string svgRaster(const std::string& stem, const MapFigure& f, double left, double top,
                      double w, double h) {
    RgbImage image(f.nx, f.ny, 150);
    for (int j = 0; j < f.ny; ++j)
        for (int i = 0; i < f.nx; ++i) {
            const float v = f.values[size_t(j) * f.nx + i];
            if (!std::isfinite(v)) continue;
            const Rgb c = mapColour(f.scale.map, (v - f.scale.lo) / (f.scale.hi - f.scale.lo));
            image.set(i, f.ny - 1 - j, c.r, c.g, c.b);
        }
    const std::string file = stem + ".raster.png";  // read back and removed
    writePng(file, image);
    const std::string png = readFile(file);
    std::remove(file.c_str());
    char head[200];
    std::snprintf(head, sizeof head,
                  "<image x='%.2f' y='%.2f' width='%.2f' height='%.2f' preserveAspectRatio='none' "
                  "style='image-rendering:pixelated' xlink:href='data:image/png;base64,",
                  left, top, w, h);
    return head + base64(png) + "'/>";
}

void setColourMap(ColourMap map) {
    if (map == ColourMap::Diverging) {
        // Blue (inside the model) - white - red (outside), ColorBrewer RdBu's ends.
        PLFLT pos[] = {0.0, 0.5, 1.0}, r[] = {0.13, 0.97, 0.70}, g[] = {0.40, 0.97, 0.09},
              b[] = {0.67, 0.97, 0.17};
        plscmap1n(256);
        plscmap1l(1, 3, pos, r, g, b, nullptr);
        return;
    }
    PLINT r[256], g[256], b[256];
    for (int k = 0; k < 256; ++k) {
        uint8_t cr, cg, cb;
        viridis(k / 255.0, cr, cg, cb);
        r[k] = cr, g[k] = cg, b[k] = cb;
    }
    plscmap1n(256);
    plscmap1(r, g, b, 256);
}

struct GridTransform {
    double x0, y0, dx, dy;
};

void cellCentre(PLFLT i, PLFLT j, PLFLT* x, PLFLT* y, PLPointer data) {
    const auto* t = static_cast<const GridTransform*>(data);
    *x = t->x0 + (i + 0.5) * t->dx;
    *y = t->y0 + (j + 0.5) * t->dy;
}

/// A field as PLplot's column-major matrix (m[i][j], i along x).
struct Matrix {
    std::vector<PLFLT> storage;
    std::vector<const PLFLT*> rows;
    Matrix(const std::vector<float>& values, int nx, int ny, double noData)
        : storage(size_t(nx) * ny), rows(nx) {
        for (int i = 0; i < nx; ++i) {
            for (int j = 0; j < ny; ++j) {
                const float v = values[size_t(j) * nx + i];
                storage[size_t(i) * ny + j] = std::isfinite(v) ? double(v) : noData;
            }
            rows[i] = &storage[size_t(i) * ny];
        }
    }
};

std::string formatLength(double mm) {
    char text[32];
    if (mm < 1)
        std::snprintf(text, sizeof text, "%g µm", std::round(mm * 1000 * 1e6) / 1e6);
    else
        std::snprintf(text, sizeof text, "%g mm", mm);
    return text;
}

/// A round length about a fifth of the width, lower left, on a white box; `pixel` is the height
/// of one pixel in mm.
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
    const std::string label = formatLength(length);
    plptex(x + length / 2, y + 11 * pixel, 1, 0, 0.5, label.c_str());
}

}  // namespace

double niceStep(double span, int parts) {
    if (!(span > 0) || parts < 1) return 1;
    const double raw = span / parts, power = std::pow(10.0, std::floor(std::log10(raw)));
    const double f = raw / power;
    return power * (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10);
}

void writeLineFigure(const std::string& stem, const LineFigure& f) {
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    for (const Curve& c : f.curves)
        for (size_t i = 0; i < std::min(c.x.size(), c.y.size()); ++i)
            if (std::isfinite(c.x[i]) && std::isfinite(c.y[i])) {
                x0 = std::min(x0, c.x[i]), x1 = std::max(x1, c.x[i]);
                y0 = std::min(y0, c.y[i]), y1 = std::max(y1, c.y[i]);
            }
    if (!(x0 <= x1)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    if (x1 - x0 < 1e-12) x0 -= 0.5, x1 += 0.5;
    if (y1 - y0 < 1e-12) y0 -= 0.5, y1 += 0.5;
    const double pad = 0.05 * (y1 - y0);
    y0 = y0 >= 0 && y0 - pad < 0 ? 0 : y0 - pad, y1 += pad;
    const int width = 760, height = f.note.empty() ? 460 : 490;
    plotTwice(stem, width, height, [&](bool) {
        const double bottom = f.note.empty() ? 0.15 : 0.2;
        plvpor(0.12, 0.96, bottom, 0.9);
        plwind(x0, x1, y0, y1);
        plcol0(LIGHT);
        plbox("g", 0, 0, "g", 0, 0);
        plcol0(BLACK);
        plbox("bcnst", 0, 0, "bcnstv", 0, 0);
        plmtex("t", 1.5, 0.5, 0.5, f.title.c_str());
        plmtex("b", 3.2, 0.5, 0.5, f.xLabel.c_str());
        plmtex("l", 5.0, 0.5, 0.5, f.yLabel.c_str());
        if (!f.note.empty()) plmtex("b", 5.0, 0.0, 0.0, f.note.c_str());
        std::vector<std::string> labels;
        std::vector<PLINT> colours, styles;
        PLINT index = FIRST_FREE;
        for (const Curve& c : f.curves) {
            colour(index, c.colour);
            pllsty(c.dashed ? 2 : 1);
            plwidth(1.6);
            polyline(c.x, c.y);
            if (!c.label.empty())
                labels.push_back(c.label), colours.push_back(index),
                    styles.push_back(c.dashed ? 2 : 1);
            ++index;
        }
        pllsty(1);
        plwidth(1);
        if (f.legend && !labels.empty())
            lineLegend(labels, colours, styles,
                       PL_POSITION_TOP | PL_POSITION_RIGHT | PL_POSITION_INSIDE, 0.02, 0.02, 1);
    });
}

void writeMapFigure(const std::string& stem, const MapFigure& f) {
    if (f.nx < 1 || f.ny < 1 || f.values.size() != size_t(f.nx) * f.ny || !(f.x1 > f.x0) ||
        !(f.y1 > f.y0))
        throw InputError("map figure " + stem + ": the grid does not match its values");
    // Plot area in pixels at the true aspect ratio, about 640 px wide or 560 px tall.
    const double aspect = (f.y1 - f.y0) / (f.x1 - f.x0);
    double pw = 640, ph = pw * aspect;
    if (ph > 560) ph = 560, pw = ph / aspect;
    const double left = 90, right = 210, top = 50, bottom = f.note.empty() ? 115 : 140;
    const int width = int(left + pw + right), height = int(top + std::max(ph, 60.0) + bottom);
    const ColourScale& s = f.scale;
    const std::string raster = svgRaster(stem, f, left, top, pw, ph);
    plotTwice(
        stem, width, height,
        [&](bool svg) {
            plvpor(left / width, (left + pw) / width, bottom / height, (bottom + ph) / height);
            plwind(f.x0, f.x1, f.y0, f.y1);
            PLFLT bx[] = {f.x0, f.x1, f.x1, f.x0}, by[] = {f.y0, f.y0, f.y1, f.y1};
            setColourMap(s.map);
            if (!svg) {
                plcol0(GREY);  // where there is no data
                plfill(4, bx, by);
            }
            const double noData = -std::numeric_limits<double>::max();
            std::vector<float> clamped(f.values);
            for (float& v : clamped)
                if (std::isfinite(v)) v = float(std::clamp(double(v), s.lo, s.hi));
            Matrix image(clamped, f.nx, f.ny, noData);
            if (!svg)
                plimagefr(image.rows.data(), f.nx, f.ny, f.x0, f.x1, f.y0, f.y1, s.lo, s.hi, s.lo,
                          s.hi, nullptr, nullptr);
            GridTransform transform{f.x0, f.y0, (f.x1 - f.x0) / f.nx, (f.y1 - f.y0) / f.ny};
            std::vector<std::string> labels;
            std::vector<PLINT> colours, styles;
            PLINT index = FIRST_FREE;
            for (const Outline& o : f.outlines) {
                const std::vector<float>& field = o.field.empty() ? f.values : o.field;
                if (field.size() != f.values.size()) continue;
                Matrix m(field, f.nx, f.ny, noData);
                colour(index, o.colour);
                pllsty(o.dashed ? 2 : 1);
                plwidth(2);
                PLFLT level = o.level;
                plcont(m.rows.data(), f.nx, f.ny, 1, f.nx, 1, f.ny, &level, 1, cellCentre,
                       &transform);
                labels.push_back(o.label), colours.push_back(index),
                    styles.push_back(o.dashed ? 2 : 1);
                ++index;
            }
            pllsty(1);
            plwidth(1);
            if (f.scaleBar && ph >= 50) scaleBar(f, (f.y1 - f.y0) / ph);
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
            if (!labels.empty())
                lineLegend(labels, colours, styles,
                           PL_POSITION_BOTTOM | PL_POSITION_OUTSIDE | PL_POSITION_VIEWPORT, 0.0,
                           55.0 / ph, int(labels.size()));
            if (!f.note.empty())
                plmtex("b", 7.2 + (labels.empty() ? 0 : 0.5), 0.0, 0.0, f.note.c_str());
        },
        raster);
}

}  // namespace vpsim::report
