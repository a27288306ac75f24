#pragma once
// What the line and map figures share about PLplot: the page on both devices, colours, lines,
// the legend. Inside src/plot only; PLplot's types stay out of the public header.

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include <plplot.h>

#include "vpsim/core/image.h"
#include "vpsim/plot/plot.h"

namespace vpsim::plot {

/// cmap0 entries every figure uses; curves and outlines take indices from FIRST_FREE on.
constexpr PLINT BLACK = 1, GREY = 2, LIGHT = 3, WHITE = 4, FIRST_FREE = 5;

/// A map's cells as pixels (rows from the top), stretched over the plot area: (left, top) and
/// size in the page's pixels.
struct Underlay {
    RgbImage cells;
    double left = 0, top = 0, width = 0, height = 0;
};

/// Draws one figure on both devices: `draw(svg)` runs inside an initialised page of
/// width x height pixels; `underlay`, when given, lies under everything PLplot draws: a PNG
/// <image> in the SVG, and in the PNG the page's pixels PLplot draws over (PLplot would draw one
/// polygon per cell on both devices: slow in cairo, huge in SVG).
void plotTwice(const std::string& stem, int width, int height,
               const std::function<void(bool svg)>& draw, const Underlay* underlay = nullptr);

/// Sets cmap0 entry `index` to `c` and draws with it.
void useColour(PLINT index, Rgb c);

/// Lines between consecutive finite points, one PLplot line per run of them.
void polyline(const std::vector<double>& x, const std::vector<double>& y);

struct LegendEntry {
    std::string label;
    PLINT colour = BLACK;
    PLINT lineStyle = 1;
    bool box = false;  ///< a filled box (bars) instead of a line
};

/// A legend at `position` (PL_POSITION_*), offset (x, y) in viewport fractions, in `columns`.
void legend(const std::vector<LegendEntry>& entries, PLINT position, double x, double y,
            int columns);

/// Characters of `label` as drawn: PLplot's escapes (#u, #d, #g) and UTF-8 continuation bytes
/// do not count.
inline size_t drawnLength(const std::string& label) {
    size_t n = 0;
    for (size_t i = 0; i < label.size(); ++i) {
        if (label[i] == '#' && i + 1 < label.size()) {
            ++i;
            continue;
        }
        n += (static_cast<unsigned char>(label[i]) & 0xC0) != 0x80;
    }
    return n;
}

/// Legend columns below a plot `plotWidth` pixels wide: as many as fit, each about 17 px per
/// character of the longest label (PLplot gives every column the longest label's width).
inline int legendColumns(size_t entries, size_t longestLabel, double plotWidth) {
    const double column = 17.0 * double(std::max<size_t>(longestLabel, 4));
    return int(
        std::clamp<size_t>(size_t((plotWidth + 60) / column), 1, std::max<size_t>(entries, 1)));
}

/// Draws `curve` (its colour already set): lines, or bars from `base`, then its error bars.
void drawCurve(const Curve& curve, double base = 0);

}  // namespace vpsim::plot
