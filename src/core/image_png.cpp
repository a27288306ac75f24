#include <png.h>

#include <cmath>
#include <cstdio>

#include "vpsim/core/error.h"
#include "vpsim/core/image.h"
#include "vpsim/core/io.h"

namespace vpsim {
namespace {

void writePngFile(const std::string& path, int width, int height, int colourType, int channels,
                  const std::vector<uint8_t>& pixels, PngEffort effort = PngEffort::Smallest) {
    if (width <= 0 || height <= 0 || pixels.size() != size_t(width) * height * channels)
        throw InputError("internal: image size does not match its pixels", path);
    writePathAtomic(path, [&](const std::string& temporary) {
        FILE* file = std::fopen(temporary.c_str(), "wb");
        if (!file) throw InputError("cannot open for writing", path);
        png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
        png_infop info = png ? png_create_info_struct(png) : nullptr;
        if (!png || !info || setjmp(png_jmpbuf(png))) {
            png_destroy_write_struct(&png, &info);
            std::fclose(file);
            throw InputError("libpng failed to write the image", path);
        }
        png_init_io(png, file);
        png_set_IHDR(png, info, width, height, 8, colourType, PNG_INTERLACE_NONE,
                     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
        if (effort == PngEffort::Quick) png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
        png_write_info(png, info);
        for (int y = 0; y < height; ++y)
            png_write_row(png, const_cast<png_bytep>(&pixels[size_t(y) * width * channels]));
        png_write_end(png, nullptr);
        png_destroy_write_struct(&png, &info);
        if (std::fclose(file) != 0) throw InputError("write failed (disk full?)", path);
    });
}

}  // namespace

void RgbImage::set(int x, int y, uint8_t r, uint8_t g, uint8_t b) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    uint8_t* p = &pixels[(size_t(y) * width + x) * 3];
    p[0] = r;
    p[1] = g;
    p[2] = b;
}

void RgbImage::line(double x0, double y0, double x1, double y1, uint8_t r, uint8_t g, uint8_t b) {
    int steps = int(std::ceil(std::max(std::abs(x1 - x0), std::abs(y1 - y0)))) + 1;
    for (int i = 0; i <= steps; ++i) {
        double t = double(i) / steps;
        set(int(std::lround(x0 + t * (x1 - x0))), int(std::lround(y0 + t * (y1 - y0))), r, g, b);
    }
}

void writePng(const std::string& path, const RgbImage& image, PngEffort effort) {
    writePngFile(path, image.width, image.height, PNG_COLOR_TYPE_RGB, 3, image.pixels, effort);
}

void writePngGrey(const std::string& path, int width, int height,
                  const std::vector<uint8_t>& grey) {
    writePngFile(path, width, height, PNG_COLOR_TYPE_GRAY, 1, grey);
}

void viridis(double t, uint8_t& r, uint8_t& g, uint8_t& b) {
    // Viridis sampled at 9 points (matplotlib's table), linearly interpolated.
    static const double table[9][3] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},
                                       {44, 113, 142}, {33, 144, 141}, {39, 173, 129},
                                       {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
    if (!(t >= 0.0)) t = 0.0;  // also maps NaN to the bottom colour
    if (t > 1.0) t = 1.0;
    double position = t * 8.0;
    int i = std::min(7, int(position));
    double f = position - i;
    r = uint8_t(std::lround(table[i][0] + f * (table[i + 1][0] - table[i][0])));
    g = uint8_t(std::lround(table[i][1] + f * (table[i + 1][1] - table[i][1])));
    b = uint8_t(std::lround(table[i][2] + f * (table[i + 1][2] - table[i][2])));
}

RgbImage heatMap(const std::vector<float>& values, int width, int height, double lo, double hi,
                 const std::vector<double>& contours) {
    RgbImage image(width, height);
    double span = hi > lo ? hi - lo : 1.0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            uint8_t r, g, b;
            viridis((values[size_t(y) * width + x] - lo) / span, r, g, b);
            image.set(x, y, r, g, b);
        }
    // A pixel is on an iso-line when the level lies between it and its right or lower neighbour.
    for (double level : contours)
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                double v = values[size_t(y) * width + x];
                bool crossing = false;
                if (x + 1 < width)
                    crossing |= (v - level) * (values[size_t(y) * width + x + 1] - level) < 0;
                if (y + 1 < height)
                    crossing |= (v - level) * (values[size_t(y + 1) * width + x] - level) < 0;
                if (crossing) image.set(x, y, 255, 255, 255);
            }
    return image;
}

}  // namespace vpsim
