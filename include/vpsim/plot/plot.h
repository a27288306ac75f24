#pragma once
/// @file
/// The one plotting layer, drawn by PLplot (Debian's libplplot: its SVG driver writes the text as
/// SVG text, its cairo driver the PNG). Every figure vpsim writes goes through it (index.html, the
/// kernel's, the scan path, the planners' reviews, `vpsim compare`, the CLI's): line figures
/// (curves, steps, bars) and map figures (a scalar field on a grid in mm at the true aspect ratio,
/// with tick labels, a colour bar with units, a scale bar, outlines in a legend and a note, e.g.
/// the share beyond the scale). Its own module right after core, so that kernel, plan and
/// optimise can draw their figures too.
///
/// Values are in display units (mJ/cm^2, um, ...): the caller converts. Text follows PLplot's
/// escapes ("#u2#d" is a superscript 2); UTF-8 (e.g. "µm") is drawn as such.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace vpsim::plot {

struct Rgb {
    uint8_t r = 0, g = 0, b = 0;
};

enum class CurveStyle {
    Line,  ///< through the points; a non-finite point breaks the line
    Bars,  ///< a filled bar from 0 to y at each x, `barWidth` wide
};

/// One curve of a line figure (or a line drawn over a map).
struct Curve {
    Curve(std::string label_ = "", std::vector<double> x_ = {}, std::vector<double> y_ = {},
          Rgb colour_ = {31, 119, 180}, bool dashed_ = false)
        : label(std::move(label_)),
          x(std::move(x_)),
          y(std::move(y_)),
          colour(colour_),
          dashed(dashed_) {}
    std::string label;  ///< in the legend; empty: not in it
    std::vector<double> x, y;
    Rgb colour;
    bool dashed;
    CurveStyle style = CurveStyle::Line;
    double barWidth = 0.8;                    ///< x units, for Bars
    std::vector<double> errorLow, errorHigh;  ///< optional error bars (same size as x)
};

struct LineFigure {
    LineFigure(std::string title_ = "", std::string xLabel_ = "", std::string yLabel_ = "",
               std::vector<Curve> curves_ = {}, std::string note_ = "", bool legend_ = true)
        : title(std::move(title_)),
          xLabel(std::move(xLabel_)),
          yLabel(std::move(yLabel_)),
          curves(std::move(curves_)),
          note(std::move(note_)),
          legend(legend_) {}
    std::string title, xLabel, yLabel;
    std::vector<Curve> curves;
    std::string note;  ///< a line under the plot
    bool legend;       ///< a legend of the curves' labels
    /// x and y to the same scale (a scan path, contours in the r-z plane).
    bool equalAspect = false;
    /// A logarithmic y axis (values <= 0 are left out; bars start at the axis's bottom).
    bool logY = false;
    /// Labels at these x instead of numeric ticks (categories, e.g. a features chart).
    std::vector<std::pair<double, std::string>> xCategories;
};

enum class ColourMap {
    Sequential,  ///< viridis, lo .. hi
    Diverging,   ///< blue - white - red, centred on 0 (lo = -hi)
    Grey,        ///< black .. white (a projector's mask)
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
    std::vector<Curve> lines;  ///< drawn over the map in its units (polygons), in the legend
    std::string note;  ///< a line under the plot (e.g. "2.1% of the surface beyond ±50 µm")
    bool scaleBar = true;
    std::string scaleUnit = "mm";  ///< the axes' unit, for the scale bar's label ("mm" or "µm")
};

/// Grids larger than this many cells on a side are averaged down before drawing, so a figure
/// stays quick to write and small (PLplot's cairo PNG and the SVG's embedded raster).
constexpr int MAX_MAP_CELLS = 1000;

/// Checks that PLplot's drivers for the figures (svg, and cairo's memcairo) are installed: without
/// them PLplot asks for a device on stdin and exits. @throw ResourceError naming the missing
/// driver and where PLplot looked (PLPLOT_DRV_DIR, else its installed directory)
void requirePlotting();

/// Writes `stem`.svg and `stem`.png (atomically). @throw InputError when a file cannot be written;
/// ResourceError as requirePlotting
void writeLineFigure(const std::string& stem, const LineFigure& figure);
/// Writes `stem`.svg and `stem`.png (atomically). @throw InputError when a file cannot be written
/// or the grid does not match its values; ResourceError as requirePlotting
void writeMapFigure(const std::string& stem, const MapFigure& figure);

/// A round axis or scale-bar length near `span` / `parts` (1, 2 or 5 times a power of ten).
double niceStep(double span, int parts);

/// `figure` with its grid (values and outline fields) averaged over blocks of cells so that
/// neither side exceeds `maxCells`; NaN cells are left out of their block's mean.
MapFigure downsampled(const MapFigure& figure, int maxCells = MAX_MAP_CELLS);

/// A polyline in a grid's cell coordinates: cell (i, j)'s centre at (i, j).
struct ContourLine {
    std::vector<double> x, y;
};

/// Where `field` (nx x ny, [j * nx + i]) crosses `level`, linear between neighbouring cells'
/// centres, joined into polylines (a closed one ends where it starts). A cell without data (NaN)
/// counts as below the level; a line beside it passes through the finite neighbour's centre.
std::vector<ContourLine> contourLines(const std::vector<float>& field, int nx, int ny,
                                      double level);

/// `path` without a trailing ".svg": the stem a figure asked for as FILE.svg is written under
/// (FILE.svg and FILE.png). @throw InputError when `path` is a directory
std::string figureStem(const std::string& path);

/// The standard palette's k-th colour (curves without a colour of their own).
Rgb paletteColour(size_t k);

}  // namespace vpsim::plot
