#pragma once
/// @file
/// The report's one plotting layer, drawn by PLplot (Debian's libplplot, SVG driver for vector
/// figures with their text as SVG text, the cairo driver for PNG). Every figure of index.html
/// and of `vpsim compare` goes through it: line figures (curves, histograms as steps) and map
/// figures (a scalar field on a grid in mm at the true aspect ratio, with tick labels, a colour
/// bar with units, a scale bar, outlines in a legend and a note, e.g. the share beyond the scale).
///
/// Values are in display units (mJ/cm^2, um, ...): the caller converts. Text follows PLplot's
/// escapes ("#u2#d" is a superscript 2); UTF-8 (e.g. "µm") is drawn as such.

#include <cstdint>
#include <string>
#include <vector>

namespace vpsim::report {

struct Rgb {
    uint8_t r = 0, g = 0, b = 0;
};

/// One curve of a line figure; a non-finite point breaks the line.
struct Curve {
    std::string label;
    std::vector<double> x, y;
    Rgb colour{31, 119, 180};
    bool dashed = false;
};

struct LineFigure {
    std::string title, xLabel, yLabel;
    std::vector<Curve> curves;
    std::string note;    ///< a line under the plot
    bool legend = true;  ///< a legend of the curves' labels (when more than one or labelled)
};

enum class ColourMap {
    Sequential,  ///< viridis, lo .. hi
    Diverging,   ///< blue - white - red, centred on 0 (lo = -hi)
};

struct ColourScale {
    ColourMap map = ColourMap::Sequential;
    double lo = 0, hi = 1;
    std::string label;                     ///< with its unit, e.g. "exposure (mJ/cm#u2#d)"
    bool capLow = false, capHigh = false;  ///< values beyond lo / hi exist (drawn as caps)
};

/// A contour of `field` (on the map's grid) at `level`: an outline of a mask at 0.5, the cured
/// region at the critical dose.
struct Outline {
    std::string label;
    std::vector<float> field;  ///< [j * nx + i]; empty: the map's values
    double level = 0.5;
    Rgb colour{230, 30, 30};
    bool dashed = false;
};

/// A scalar field on a regular grid of cells, row j = 0 at y0.
struct MapFigure {
    std::string title, xLabel = "x (mm)", yLabel = "y (mm)";
    int nx = 0, ny = 0;
    double x0 = 0, x1 = 1, y0 = 0, y1 = 1;  ///< mm, outer edges of the cells
    std::vector<float> values;              ///< display units; NaN: no data (drawn grey)
    ColourScale scale;
    std::vector<Outline> outlines;
    std::string note;  ///< a line under the plot (e.g. "2.1% of the surface beyond ±50 µm")
    bool scaleBar = true;
};

/// Writes `stem`.svg and `stem`.png (atomically). @throw InputError when a file cannot be written
void writeLineFigure(const std::string& stem, const LineFigure& figure);
/// Writes `stem`.svg and `stem`.png (atomically). @throw InputError when a file cannot be written
/// or the grid does not match its values
void writeMapFigure(const std::string& stem, const MapFigure& figure);

/// A round axis or scale-bar length near `span` / `parts` (1, 2 or 5 times a power of ten).
double niceStep(double span, int parts);

}  // namespace vpsim::report
