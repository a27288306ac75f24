#pragma once
/// @file
/// Raster pictures: PNG images and heat maps with a colour map (figures with axes are drawn by
/// the plotting layer, plot/plot.h).

#include <cstdint>
#include <string>
#include <vector>

namespace vpsim {

/// 8-bit RGB image, rows from top to bottom.
struct RgbImage {
    int width = 0, height = 0;
    std::vector<uint8_t> pixels;  ///< width*height*3
    RgbImage() = default;
    RgbImage(int w, int h, uint8_t grey = 255)
        : width(w), height(h), pixels(size_t(w) * h * 3, grey) {}
    void set(int x, int y, uint8_t r, uint8_t g, uint8_t b);
    /// Draws a 1-pixel line (clipped to the image).
    void line(double x0, double y0, double x1, double y1, uint8_t r, uint8_t g, uint8_t b);
};

/// How hard libpng works for a small file: Smallest tries every row filter on each row; Quick
/// filters none (figures of flat colours: about the same size, a third of the time).
enum class PngEffort { Smallest, Quick };

/// Writes an RGB image as PNG (atomically). @throw InputError when the file cannot be written.
void writePng(const std::string& path, const RgbImage& image,
              PngEffort effort = PngEffort::Smallest);
/// Writes an 8-bit greyscale image (e.g. a DLP mask) as PNG.
void writePngGrey(const std::string& path, int width, int height, const std::vector<uint8_t>& grey);

/// Maps t in [0,1] to the viridis colour map.
void viridis(double t, uint8_t& r, uint8_t& g, uint8_t& b);

/// Renders a row-major scalar field (values[y*width+x], y=0 at the top) with viridis between lo
/// and hi; `contours` draws iso-lines in white at those levels.
RgbImage heatMap(const std::vector<float>& values, int width, int height, double lo, double hi,
                 const std::vector<double>& contours = {});

}  // namespace vpsim
