// The page every figure is drawn on, twice: PLplot's SVG, and a PNG that cairo draws in memory
// over the map's cells (plplot_page.h).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "plplot_page.h"
#include "vpsim/core/base64.h"
#include "vpsim/core/error.h"
#include "vpsim/core/image.h"
#include "vpsim/core/io.h"

namespace vpsim::plot {

namespace {

/// PLplot keeps its streams in global state: one figure at a time.
std::mutex& plplotMutex() {
    static std::mutex mutex;
    return mutex;
}

/// The cells one pixel covers along an axis and how much of the pixel each covers.
struct PixelCover {
    int firstCell = 0;
    std::vector<float> shares;  ///< of cells firstCell, firstCell + 1, ...; sum <= 1
};

/// For the page's pixels [0, pageSize) along an axis: the `cells` that span `extent` pixels from
/// `start`, by the length of each pixel they cover (cairo's anti-aliasing of the cells' edges,
/// without its seams).
std::vector<PixelCover> pixelCovers(double start, double extent, int cells, int pageSize) {
    std::vector<PixelCover> covers(size_t(std::max(0, pageSize)));
    const double cell = extent / cells;  // pixels
    for (int p = 0; p < pageSize; ++p) {
        const double a = std::max(double(p), start), b = std::min(p + 1.0, start + extent);
        if (!(b > a)) continue;
        PixelCover& c = covers[size_t(p)];
        c.firstCell = std::clamp(int(std::floor((a - start) / cell)), 0, cells - 1);
        const int last = std::clamp(int(std::ceil((b - start) / cell)) - 1, c.firstCell, cells - 1);
        for (int k = c.firstCell; k <= last; ++k)
            c.shares.push_back(float(std::max(
                0.0, std::min(b, start + (k + 1) * cell) - std::max(a, start + k * cell))));
    }
    return covers;
}

/// A white RGBA page of width x height with the underlay's cells on it, each pixel the cells
/// it covers weighted by the area they cover.
std::vector<unsigned char> pageWithUnderlay(int width, int height, const Underlay* underlay) {
    std::vector<unsigned char> page(size_t(width) * height * 4, 255);
    if (!underlay || underlay->cells.width < 1 || underlay->cells.height < 1) return page;
    const Underlay& u = *underlay;
    const std::vector<PixelCover> columns = pixelCovers(u.left, u.width, u.cells.width, width);
    const std::vector<PixelCover> rows = pixelCovers(u.top, u.height, u.cells.height, height);
    for (int y = 0; y < height; ++y) {
        const PixelCover& row = rows[size_t(y)];
        for (int x = 0; x < width && !row.shares.empty(); ++x) {
            const PixelCover& column = columns[size_t(x)];
            if (column.shares.empty()) continue;
            float rgb[3] = {0, 0, 0}, covered = 0;
            for (size_t r = 0; r < row.shares.size(); ++r) {
                const uint8_t* cells =
                    &u.cells.pixels[(size_t(row.firstCell + int(r)) * u.cells.width +
                                     size_t(column.firstCell)) *
                                    3];
                for (size_t c = 0; c < column.shares.size(); ++c) {
                    const float w = row.shares[r] * column.shares[c];
                    for (int k = 0; k < 3; ++k) rgb[k] += w * cells[c * 3 + k];
                    covered += w;
                }
            }
            unsigned char* out = &page[(size_t(y) * width + x) * 4];
            for (int k = 0; k < 3; ++k)  // the rest of a pixel at the edge is the white page
                out[k] = uint8_t(std::lround(std::min(255.0f, rgb[k] + (1 - covered) * 255)));
        }
    }
    return page;
}

/// The underlay as an SVG <image>: its cells as an embedded PNG.
std::string svgImage(const std::string& stem, const Underlay& u) {
    const std::string file = stem + ".raster.png";  // read back and removed
    writePng(file, u.cells, PngEffort::Quick);
    const std::string png = readFile(file);
    std::remove(file.c_str());
    char head[200];
    std::snprintf(head, sizeof head,
                  "<image x='%.2f' y='%.2f' width='%.2f' height='%.2f' preserveAspectRatio='none' "
                  "style='image-rendering:pixelated' xlink:href='data:image/png;base64,",
                  u.left, u.top, u.width, u.height);
    return head + base64(png) + "'/>";
}

/// `svgFile` with `image` inserted after its background rectangle (under everything drawn).
void insertUnder(const std::string& svgFile, const std::string& image, const std::string& path) {
    std::string text = readFile(svgFile);
    const size_t background = text.find("<rect");
    const size_t end = text.find("/>", background);
    if (background == std::string::npos || end == std::string::npos)
        throw InputError(path + ": PLplot's SVG has no background to draw over");
    text.insert(end + 2, "\n" + image);
    std::ofstream out(svgFile, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out.flush()) throw InputError(path + ": cannot be written");
}

/// A new PLplot stream with the colours every figure uses; the device and page are set after.
void beginStream() {
    PLINT stream = 0;
    plmkstrm(&stream);
    plscmap0n(32);
    plscolbg(255, 255, 255);
    plscol0(BLACK, 0, 0, 0);
    plscol0(GREY, 150, 150, 150);
    plscol0(LIGHT, 225, 225, 225);
    plscol0(WHITE, 255, 255, 255);
}

void beginPage() {
    plinit();
    pladv(0);
    plschr(0, 0.85);
}

/// Refuses `needed` drivers (file stems in PLplot's drivers directory) that are not there. PLplot
/// reads the same DIR/NAME.driver_info files; checking them here keeps its own messages and its
/// prompt for another device out of vpsim's output.
void checkDrivers(const std::vector<std::string>& needed) {
    const char* env = std::getenv("PLPLOT_DRV_DIR");
    const std::string dir = env ? env : VPSIM_PLPLOT_DRIVERS_DIR;
    for (const std::string& driver : needed) {
        std::error_code error;
        if (std::filesystem::is_regular_file(dir + "/" + driver + ".driver_info", error)) continue;
        throw ResourceError("cannot draw figures: PLplot's " + driver + " driver is not in " + dir +
                            (env ? " (PLPLOT_DRV_DIR)" : "") +
                            "; install libplplot17 and plplot-driver-cairo, or leave \"figures\" "
                            "out of simulation.outputs");
    }
}

}  // namespace

void requirePlotting() {
    checkDrivers({"svg", "cairo"});  // cairo holds memcairo
}

void plotTwice(const std::string& stem, int width, int height,
               const std::function<void(bool svg)>& draw, const Underlay* underlay) {
    requirePlotting();
    std::lock_guard<std::mutex> lock(plplotMutex());
    writePathAtomic(stem + ".svg", [&](const std::string& temporary) {
        beginStream();
        plsdev("svg");
        plsfnam(temporary.c_str());
        const std::string geometry = std::to_string(width) + "x" + std::to_string(height);
        plsetopt("geometry", geometry.c_str());
        beginPage();
        draw(true);
        plend1();
        if (underlay) insertUnder(temporary, svgImage(stem, *underlay), stem + ".svg");
    });
    // The PNG: cairo draws over the page in memory (the underlay already on it), libpng writes it.
    std::vector<unsigned char> page = pageWithUnderlay(width, height, underlay);
    beginStream();
    plsdev("memcairo");
    plsmema(width, height, page.data());
    beginPage();
    draw(false);
    plend1();
    RgbImage image(width, height);
    for (size_t p = 0; p < size_t(width) * height; ++p)
        std::copy_n(&page[p * 4], 3, &image.pixels[p * 3]);
    writePng(stem + ".png", image, PngEffort::Quick);
}

}  // namespace vpsim::plot
